/**
 * @file sim_fault_cond.c
 * @brief The observable condition of a jam, an open winding, a broken spring or a supply sag in the plant's truth (see the header).
 */
#include "sim_fault_cond.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

void sim_cond_init(sim_cond_t *c, const plant_config_t *pc, const plant_fault_list_t *faults)
{
    unsigned k;
    memset(c, 0, sizeof *c);
    c->pc = *pc;
    c->kind = PLANT_FAULT_KIND_COUNT;
    c->seg_start_s = (double)NAN;
    c->t_s = (double)NAN;
    if (faults == NULL) {
        return;
    }
    for (k = 0u; k < faults->n && k < PLANT_FAULT_LIST_MAX; ++k) {
        if (faults->spec[k].kind == PLANT_FAULT_JAM || faults->spec[k].kind == PLANT_FAULT_WINDING_OPEN ||
            faults->spec[k].kind == PLANT_FAULT_SPRING_WEAK || faults->spec[k].kind == PLANT_FAULT_SUPPLY_SAG) {
            c->kind = faults->spec[k].kind;
            c->onset_s = faults->spec[k].t_s;
            return;
        }
    }
}

/* Does the bridge ask a jammed plate at phi to move (see the header)? */
static int jam_demand(const sim_cond_t *c, const sim_row_t *row, double phi)
{
    const plant_config_t *p = &c->pc;
    if (!row->bridge_enable) {
        return 0;
    }
    if (!isnan(row->target_rad)) {
        const double lo = p->phi_closed_rad + SIM_COND_STOP_MARGIN_RAD;
        const double hi = p->phi_open_rad - SIM_COND_STOP_MARGIN_RAD;
        const double tgt = row->target_rad < lo ? lo : row->target_rad > hi ? hi : row->target_rad;
        return fabs(tgt - phi) >= SIM_COND_JAM_ERR_RAD;
    }
    {
        /* open loop: toward the stop the voltage pushes to, beyond the healthy breakaway */
        const double s = row->u_applied_V > 0.0 ? 1.0 : -1.0;
        const double stop = s > 0.0 ? p->phi_open_rad : p->phi_closed_rad;
        const double spring = p->M0_Nm * (phi > 0.0 ? 1.0 : -1.0) + p->c_Nm_rad * phi;
        const double need = p->Ms_Nm + fmax(0.0, s * spring);
        return fabs(stop - phi) >= SIM_COND_JAM_ERR_RAD &&
               p->n_gear * p->Kt_Nm_A * fabs(row->u_applied_V) / p->R_ohm >= need;
    }
}

void sim_cond_row(const sim_row_t *row, void *user)
{
    sim_cond_t *c = (sim_cond_t *)user;
    const unsigned len = SIM_COND_STILL_N + 1u;
    const double phi = row->truth[TVM_PHI];
    const int new_code = (row->dtc_confirmed & ~c->dtc_prev) != 0u;
    c->phi[c->n % len] = phi;
    ++c->n;
    c->dtc_prev = row->dtc_confirmed;
    if (c->kind == PLANT_FAULT_KIND_COUNT || !isnan(c->t_s) || row->t_s < c->onset_s - 1e-9) {
        return;
    }
    if (c->kind == PLANT_FAULT_SPRING_WEAK) {
        if (row->bridge_enable) {
            c->t_s = row->t_s;
        }
        return;
    }
    if (c->kind == PLANT_FAULT_SUPPLY_SAG) {
        if (row->supply_V < SIM_COND_SUPPLY_LOW_V) {
            c->t_s = row->t_s;
        }
        return;
    }
    if (c->kind == PLANT_FAULT_WINDING_OPEN) {
        const double emf = c->pc.n_gear * c->pc.Ke_V_s_rad * row->truth[TVM_W];
        if (row->bridge_enable && fabs(row->u_applied_V) >= SIM_COND_OPEN_V &&
            fabs(row->u_applied_V - emf) >= SIM_COND_OPEN_V) {
            c->t_s = row->t_s;
        }
        return;
    }
    {
        /* the angle SIM_COND_STILL_N samples before this one */
        const int still = c->n >= len && fabs(phi - c->phi[c->n % len]) < SIM_COND_STILL_RAD;
        if (jam_demand(c, row, phi) && still) {
            if (isnan(c->seg_start_s)) {
                c->seg_start_s = row->t_s;
            }
            if (row->t_s - c->seg_start_s >= SIM_COND_STALL_S - 1e-9 || new_code) {
                c->t_s = c->seg_start_s;
            }
        } else {
            if (new_code && !isnan(c->seg_start_s)) {
                c->t_s = c->seg_start_s; /* a code's action ended the stall */
            }
            c->seg_start_s = (double)NAN;
        }
    }
}

double sim_cond_time(const sim_cond_t *c)
{
    return c != NULL ? c->t_s : (double)NAN;
}
