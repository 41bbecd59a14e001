/**
 * @file sim_fault_run.h
 * @brief Test helpers shared by the diagnostic tests (test_detect, test_hwdiag): one simulated
 *        run with at most one injected fault, and "was a code ever pending or confirmed".
 */
#ifndef SIM_FAULT_RUN_H
#define SIM_FAULT_RUN_H

#include <math.h>

#include "plant_fault.h"
#include "sim.h"
#include "tv_status.h"
#include "tv_test.h"

/* Run *opt (its faults replaced by spec, a host_sim --fault SPEC, or none when NULL). */
static inline void sim_fault_run_opt(sim_options_t *opt, const char *spec, sim_result_t *r)
{
    static plant_fault_list_t l;
    plant_fault_list_clear(&l);
    opt->faults = NULL;
    if (spec != NULL) {
        TV_CHECK_EQ_INT(plant_fault_list_add(&l, spec, NULL, 0u), TV_OK);
        opt->faults = &l;
    }
    TV_CHECK_EQ_INT(sim_run(opt, r), TV_OK);
}

/* One run with one fault (spec NULL: healthy), of duration_s [s] (0: the scenario's own). */
static inline void sim_fault_run(const plant_config_t *pc, const app_config_t *ac, sim_scenario_t scn, uint64_t seed,
                                 const char *spec, double duration_s, sim_result_t *r)
{
    sim_options_t opt;
    sim_options_default(&opt);
    if (duration_s > 0.0) {
        opt.duration_s = duration_s;
    }
    opt.scenario = scn;
    opt.seed = seed;
    opt.plant = pc;
    opt.app = ac;
    sim_fault_run_opt(&opt, spec, r);
}

/* 1 when code d was pending or confirmed at any time of the run. */
static inline int sim_dtc_ever(const sim_result_t *r, diag_dtc_t d)
{
    return isfinite(r->dtc_confirm_t_s[d]) || isfinite(r->dtc_pending_t_s[d]);
}

#endif /* SIM_FAULT_RUN_H */
