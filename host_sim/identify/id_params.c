/**
 * @file id_params.c
 * @brief The parameter file of an identification (see id_params.h).
 */
#include "id_params.h"

#include <math.h>
#include <stdio.h>

#include "numfmt.h"
#include "stop_learn.h"
#include "tv_param_table.h"
#include "tv_status.h"

static void put_key(FILE *f, const char *key, double v, int identified, const char *note)
{
    char num[NUMFMT_MAX];
    const int id = tvp_find(key);
    (void)numfmt_g9(num, v);
    if (identified && id >= 0 && tvp_check(id, v) == 0) {
        fprintf(f, "%s = %s    # %s\n", key, num, note);
    } else if (identified) {
        fprintf(f, "# %s = %s    # outside the key's range: not written, the default is kept\n", key, num);
    } else {
        fprintf(f, "# %s: not identified (%s): the default is kept\n", key, note);
    }
}

static void put_param(FILE *f, const char *key, const id_result_t *r, id_param_t p, double scale)
{
    char note[ID_WHY_MAX + 64];
    if (r->identified[p]) {
        (void)snprintf(note, sizeof note, "identified, sigma %.3g %s", r->sigma[p] * scale, id_param_unit(p));
    } else {
        (void)snprintf(note, sizeof note, "%s", r->why[p]);
    }
    put_key(f, key, r->value[p] * scale, r->identified[p], note);
}

int id_write_params(FILE *f, const char *log_name, const id_result_t *r, double gear)
{
    const int stops = r->identified[ID_P_K_STOP] && r->identified[ID_P_STOP_EXP];
    sl_config_t slc;
    sl_config_default(&slc);
    fprintf(f, "# Parameter file written by identify from %s (host_sim/identify/identify.h):\n"
               "# the model's parameters identified from the log, with their standard deviations.\n"
               "# Keys not written keep the defaults of the program that reads this file.\n",
            log_name);
    if (isnan(r->r_log_temp_C)) {
        fprintf(f, "# model.R_ohm is the winding's resistance at 20 degC: the log's as it is (its temperature was not given)\n");
    } else {
        fprintf(f, "# model.R_ohm is the winding's resistance at 20 degC, referred from the log's %.4g degC (copper)\n",
                r->r_log_temp_C);
    }
    put_param(f, "model.R_ohm", r, ID_P_R, 1.0);
    put_param(f, "model.L_H", r, ID_P_L, 1.0);
    fprintf(f, "# the log shows n Ke = n Kt = %.6g V s/rad (Kt = Ke in SI units, tied); split with n = %g:\n",
            r->value[ID_P_NKE], gear);
    put_key(f, "model.n_gear", gear, r->identified[ID_P_NKE], "given (--gear), not identified: only n Ke is seen");
    put_param(f, "model.Ke_V_s_rad", r, ID_P_NKE, 1.0 / gear);
    put_param(f, "model.Kt_Nm_A", r, ID_P_NKE, 1.0 / gear);
    put_param(f, "model.J_kg_m2", r, ID_P_J, 1.0);
    put_param(f, "model.M0_Nm", r, ID_P_M0, 1.0);
    put_param(f, "model.c_Nm_rad", r, ID_P_C, 1.0);
    put_param(f, "model.Mc_Nm", r, ID_P_MC, 1.0);
    if (r->identified[ID_P_MC] && !(r->identified[ID_P_MS] && r->value[ID_P_MS] >= r->value[ID_P_MC])) {
        /* Mc is known and Ms is not, or is below it: the rule Ms >= Mc of every reader */
        char note[ID_WHY_MAX + 128];
        (void)snprintf(note, sizeof note, "static friction not identified (%s): set to Mc, the least Ms >= Mc allows",
                       r->identified[ID_P_MS] ? "below Mc" : r->why[ID_P_MS]);
        put_key(f, "model.Ms_Nm", r->value[ID_P_MC], 1, note);
    } else {
        put_param(f, "model.Ms_Nm", r, ID_P_MS, 1.0);
    }
    put_param(f, "model.ws_rad_s", r, ID_P_WS, 1.0);
    put_param(f, "model.Kv_Nm_s_rad", r, ID_P_KV, 1.0);
    put_param(f, "model.phi_closed_rad", r, ID_P_PHI_CLOSED, 1.0);
    put_param(f, "model.phi_open_rad", r, ID_P_PHI_OPEN, 1.0);
    put_param(f, "model.k_stop_Nm_rad", r, ID_P_K_STOP, 1.0);
    put_param(f, "model.stop_exponent", r, ID_P_STOP_EXP, 1.0);
    if (stops) {
        /* d_stop = (lambda / k) x k: the impacts' damping ratio, else the stop-learning rule's */
        char note[ID_WHY_MAX + 64];
        const double ratio = r->identified[ID_P_STOP_DAMP] ? r->value[ID_P_STOP_DAMP] : (double)slc.lambda_per_k_s_rad;
        if (r->identified[ID_P_STOP_DAMP]) {
            (void)snprintf(note, sizeof note, "identified by the impacts: lambda / k = %.3g s/rad", ratio);
        } else {
            (void)snprintf(note, sizeof note, "lambda / k = %.3g s/rad: %s", ratio, r->why[ID_P_STOP_DAMP]);
        }
        put_key(f, "model.d_stop_Nm_s_rad", ratio * r->value[ID_P_K_STOP], 1, note);
        if (r->identified[ID_P_STOP_DAMP]) {
            /* the start-up stop learning re-fits k and the onsets every start: at the exponent and
             * with the damping ratio the impacts chose, which its slow approach cannot see */
            /* the identified stiffness as the secant at SL_P_REF_RAD the routine bounds, +-1 %: its fit
             * then moves the onsets only */
            const double ksec = r->value[ID_P_K_STOP] * pow((double)SL_P_REF_RAD, r->value[ID_P_STOP_EXP] - 1.0);
            fputs("# start-up stop learning (firmware/app/stop_learn.h): the contact law identified here is kept,\n"
                  "# the routine re-learns the onsets only (they move with wear and temperature)\n",
                  f);
            put_key(f, "stop_learn.e_min", r->value[ID_P_STOP_EXP], 1, "the exponent identified");
            put_key(f, "stop_learn.e_max", r->value[ID_P_STOP_EXP], 1, "the same: fixed");
            put_key(f, "stop_learn.lambda_per_k_s_rad", ratio, 1, "the damping ratio identified");
            put_key(f, "stop_learn.k_min_Nm_rad", 0.99 * ksec, 1, "the stiffness identified, as a secant at 2.5 mrad, -1 %");
            put_key(f, "stop_learn.k_max_Nm_rad", 1.01 * ksec, 1, "the same, +1 %");
            /* the online impact learning is for a law nobody measured: on identified units it
             * moved the identified (or the true) law off and doubled the 12 V sine's velocity
             * error (README "Identification", step 6) */
            fputs("# online impact learning (firmware/app/impact_learn.h) off: it learns a law nobody measured;\n"
                  "# from the law identified here it moved away (README \"Identification\")\n",
                  f);
            put_key(f, "impact_learn.enable", 0.0, 1, "the contact law identified above is kept in service");
        }
    } else {
        put_key(f, "model.d_stop_Nm_s_rad", 0.0, 0, "the contact law was not identified");
    }
    {
        /* the diagnostic bounds relative to the unit's own model: only when the motor, the
         * inertia, the friction and the springs are all the unit's (identified), since those
         * are what the friction and preload checks judge against */
        static const id_param_t need[] = {ID_P_R, ID_P_NKE, ID_P_J, ID_P_M0, ID_P_C, ID_P_MC, ID_P_MS, ID_P_KV};
        size_t k;
        const char *missing = NULL;
        for (k = 0; k < sizeof need / sizeof need[0] && missing == NULL; ++k) {
            if (!r->identified[need[k]]) {
                missing = id_param_name(need[k]);
            }
        }
        fputs("# the diagnostic bounds (firmware/diag/diag_detect.h): ", f);
        if (missing == NULL) {
            fputs("the motor, inertia, friction and springs above are this unit's own,\n"
                  "# so friction and preload are judged relative to them (diag_detect_config_identified())\n"
                  "diag.identified = 1\n",
                  f);
        } else {
            fprintf(f, "the class's (%s was not identified)\n", missing);
        }
    }
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

