/**
 * @file sim_mc.c
 * @brief Monte Carlo over seeds: per-tick NEES and NIS averages.
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"

#include "tv_status.h"

/* ------------------------------------------------------------------------------------------ */
/* Monte Carlo                                                                                 */
/* ------------------------------------------------------------------------------------------ */

/* Per-tick accumulation across seeds. */
typedef struct {
    double *nees_sum;  /* per tick index */
    uint32_t *nees_cnt;
    uint32_t n_slots;
    double nees_total;
    double nees_n;
    double nis_total;
    double nis_dof_total;
    double nis_n;
} sim_mc_acc_t;

static void sim_mc_row(const sim_row_t *row, void *user)
{
    sim_mc_acc_t *acc = (sim_mc_acc_t *)user;
    const uint32_t idx = (uint32_t)floor(row->t_s / SIM_TICK_S + 0.5);
    if (row->t_s < SIM_TRANSIENT_S - 1e-9 || idx >= acc->n_slots) {
        return;
    }
    if (sim_finite(row->nees)) {
        acc->nees_sum[idx] += row->nees;
        ++acc->nees_cnt[idx];
        acc->nees_total += row->nees;
        acc->nees_n += 1.0;
    }
    if (row->nis_dof > 0 && sim_finite(row->nis)) {
        acc->nis_total += row->nis;
        acc->nis_dof_total += (double)row->nis_dof;
        acc->nis_n += 1.0;
    }
}

int sim_monte_carlo(const sim_options_t *opt, uint32_t n_seeds, sim_progress_fn progress, void *user,
                    sim_mc_result_t *out)
{
    sim_options_t o;
    sim_mc_acc_t acc;
    sim_result_t r;
    double duration_s;
    uint32_t s;
    int e;
    int a;
    int rc = TV_OK;
    if (opt == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    memset(out, 0, sizeof *out);
    if (n_seeds == 0u || n_seeds > SIM_MC_SEEDS_MAX) {
        return TV_ERR_RANGE;
    }
    rc = sim_check_options(opt);
    if (rc != TV_OK) {
        return rc;
    }
    duration_s = opt->duration_s > 0.0 ? opt->duration_s : sim_scenario_duration_s(opt->scenario);
    memset(&acc, 0, sizeof acc);
    acc.n_slots = (uint32_t)floor(duration_s / SIM_TICK_S + 0.5) + 1u;
    acc.nees_sum = (double *)calloc(acc.n_slots, sizeof *acc.nees_sum);
    acc.nees_cnt = (uint32_t *)calloc(acc.n_slots, sizeof *acc.nees_cnt);
    if (acc.nees_sum == NULL || acc.nees_cnt == NULL) {
        free(acc.nees_sum);
        free(acc.nees_cnt);
        return TV_ERR_IO;
    }
    o = *opt;
    o.csv = NULL;
    o.row_fn = sim_mc_row;
    o.row_user = &acc;
    out->scenario = opt->scenario;
    out->n_seeds = n_seeds;
    out->first_seed = opt->seed;
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        for (a = 0; a < TVM_NX; ++a) {
            out->rmse_max[e][a] = 0.0;
        }
    }
    for (s = 0; s < n_seeds; ++s) {
        o.seed = opt->seed + s;
        rc = sim_run(&o, &r);
        if (rc != TV_OK) {
            break;
        }
        out->duration_s = r.duration_s;
        out->n_ticks_scored = r.n_scored;
        for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
            for (a = 0; a < TVM_NX; ++a) {
                out->rmse_mean[e][a] += r.rmse[e][a] / (double)n_seeds;
                if (!(r.rmse[e][a] <= out->rmse_max[e][a])) {
                    out->rmse_max[e][a] = r.rmse[e][a]; /* NaN propagates */
                }
            }
        }
        if (r.faults != 0u) {
            ++out->runs_with_faults;
        }
        out->ekf_rejections += r.ekf_rejections;
        out->missing_samples += r.missing_samples;
        out->paper_printed_resets += r.paper_printed_resets;
        if (progress != NULL) {
            progress(s + 1u, n_seeds, user);
        }
    }
    if (rc == TV_OK) {
        const double m = (double)n_seeds;
        uint32_t in_band = 0u;
        uint32_t scored = 0u;
        uint32_t k;
        out->band_lo = sim_chi2_quantile(SIM_BAND_P_LO, 3.0 * m) / m;
        out->band_hi = sim_chi2_quantile(SIM_BAND_P_HI, 3.0 * m) / m;
        for (k = 0; k < acc.n_slots; ++k) {
            if ((double)k * SIM_TICK_S < SIM_TRANSIENT_S - 1e-9) {
                continue;
            }
            if (acc.nees_cnt[k] == 0u) {
                continue; /* no run ticked here (beyond the end, or a dropped tick) */
            }
            ++scored;
            if (acc.nees_cnt[k] == n_seeds) {
                const double avg = acc.nees_sum[k] / m;
                if (avg >= out->band_lo && avg <= out->band_hi) {
                    ++in_band;
                }
            }
        }
        out->frac_ticks_in_band = scored > 0u ? (double)in_band / (double)scored : SIM_NAN;
        out->anees = acc.nees_n > 0.0 ? acc.nees_total / acc.nees_n : SIM_NAN;
        out->anees_lo = acc.nees_n > 0.0 ? sim_chi2_quantile(SIM_BAND_P_LO, 3.0 * acc.nees_n) / acc.nees_n : SIM_NAN;
        out->anees_hi = acc.nees_n > 0.0 ? sim_chi2_quantile(SIM_BAND_P_HI, 3.0 * acc.nees_n) / acc.nees_n : SIM_NAN;
        out->anis = acc.nis_n > 0.0 ? acc.nis_total / acc.nis_n : SIM_NAN;
        out->nis_dof_avg = acc.nis_n > 0.0 ? acc.nis_dof_total / acc.nis_n : SIM_NAN;
    }
    free(acc.nees_sum);
    free(acc.nees_cnt);
    return rc;
}
