/**
 * @file nis_monitor.c
 * @brief Windowed per-channel NIS test (see nis_monitor.h).
 */
#include "nis_monitor.h"

#include <stddef.h>
#include <string.h>

#include "tv_status.h"

void nism_config_default(nism_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->window = 100u;
    cfg->threshold = TV_R(10.0);
    cfg->trip_blocks = 3u;
}

int nism_init(nism_t *m, const nism_config_t *cfg)
{
    if (m == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(cfg->threshold)) {
        return TV_ERR_NONFINITE;
    }
    if (cfg->window == 0u || cfg->window > NISM_WINDOW_MAX || !(cfg->threshold > TV_R(0.0)) ||
        cfg->trip_blocks == 0u) {
        return TV_ERR_CONFIG;
    }
    memset(m, 0, sizeof *m);
    m->cfg = *cfg;
    return TV_OK;
}

unsigned nism_update(nism_t *m, const ekf_innov_t *in)
{
    int ch;
    if (m == NULL || in == NULL) {
        return 0u;
    }
    for (ch = 0; ch < EKF_NCH; ++ch) {
        const tv_real_t v = in->nis[ch];
        if (!in->used[ch] || !(v >= TV_R(0.0)) || !TV_IS_FINITE(v)) {
            continue;
        }
        m->sum[ch] += v;
        if (++m->n[ch] >= m->cfg.window) {
            const tv_real_t mean = m->sum[ch] / (tv_real_t)m->n[ch];
            m->last_mean[ch] = mean;
            m->sum[ch] = TV_R(0.0);
            m->n[ch] = 0u;
            if (mean > m->cfg.threshold) {
                if (m->failed[ch] < m->cfg.trip_blocks) {
                    ++m->failed[ch];
                }
                if (m->failed[ch] >= m->cfg.trip_blocks && (m->flags & NISM_FLAG(ch)) == 0u) {
                    m->flags |= NISM_FLAG(ch);
                    ++m->episodes;
                }
            } else {
                m->failed[ch] = 0u;
                m->flags &= ~NISM_FLAG(ch);
            }
        }
    }
    return m->flags;
}
