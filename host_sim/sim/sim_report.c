/**
 * @file sim_report.c
 * @brief Report writers of the simulation: CSV rows, metrics text and JSON.
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"

#include "tv_status.h"

/* ------------------------------------------------------------------------------------------ */
/* Output                                                                                      */
/* ------------------------------------------------------------------------------------------ */

static const char *const s_csv_columns =
    "t_s,i_true_A,w_true_rad_s,phi_true_rad,adc_current,adc_tps1,adc_tps2,adc_supply,u_applied_V,u_bridge_V,"
    "duty,bridge_enable,target_rad,i_meas_A,w_meas_rad_s,phi_meas_rad,i_est_A,w_est_rad_s,phi_est_rad,"
    "i_sigma_A,w_sigma_rad_s,phi_sigma_rad,innov_i_A,innov_w_rad_s,innov_phi_rad,innov_i_sigma_A,"
    "innov_w_sigma_rad_s,innov_phi_sigma_rad,nis,nis_dof,nees,mode,faults,ekf_status,missing_samples,"
    "i_paper_A,w_paper_rad_s,phi_paper_rad,i_paper_sigma_A,w_paper_sigma_rad_s,phi_paper_sigma_rad,"
    "i_printed_A,w_printed_rad_s,phi_printed_rad,i_eq12_A,w_eq12_rad_s,phi_eq12_rad,i_eq12x_A,w_eq12x_rad_s,"
    "phi_eq12x_rad\n";

int sim_csv_header(FILE *f)
{
    if (f == NULL) {
        return TV_ERR_NULL;
    }
    return fputs(s_csv_columns, f) < 0 ? TV_ERR_IO : TV_OK;
}

int sim_csv_row(FILE *f, const sim_row_t *r)
{
    int n;
    if (f == NULL || r == NULL) {
        return TV_ERR_NULL;
    }
    n = fprintf(f,
                "%.9g,%.9g,%.9g,%.9g,%u,%u,%u,%u,%.9g,%.9g,%.9g,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,"
                "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%d,%lu,%d,%lu,"
                "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                r->t_s, r->truth[0], r->truth[1], r->truth[2], (unsigned)r->adc[0], (unsigned)r->adc[1],
                (unsigned)r->adc[2], (unsigned)r->adc[3], r->u_applied_V, r->u_bridge_V, r->duty, r->bridge_enable,
                r->target_rad, r->z[EKF_CH_CURRENT], r->z[EKF_CH_VELOCITY], r->z[EKF_CH_ANGLE], r->x[0], r->x[1],
                r->x[2], r->sigma[0], r->sigma[1], r->sigma[2], r->innov[EKF_CH_CURRENT], r->innov[EKF_CH_VELOCITY],
                r->innov[EKF_CH_ANGLE], r->innov_sigma[EKF_CH_CURRENT], r->innov_sigma[EKF_CH_VELOCITY],
                r->innov_sigma[EKF_CH_ANGLE], r->nis, r->nis_dof, r->nees, r->mode, (unsigned long)r->faults,
                r->ekf_status, (unsigned long)r->missing_samples, r->x_paper[0], r->x_paper[1], r->x_paper[2],
                r->sigma_paper[0], r->sigma_paper[1], r->sigma_paper[2], r->x_printed[0], r->x_printed[1],
                r->x_printed[2], r->x_eq12[0], r->x_eq12[1], r->x_eq12[2], r->x_eq12x[0], r->x_eq12x[1], r->x_eq12x[2]);
    return n < 0 ? TV_ERR_IO : TV_OK;
}

/* JSON number or null. */
static void sim_jnum(FILE *f, double v)
{
    if (sim_finite(v)) {
        fprintf(f, "%.9g", v);
    } else {
        fputs("null", f);
    }
}

/* rmse: SIM_EST_COUNT x TVM_NX, row-major */
static void sim_print_rmse_rows(FILE *f, const double *rmse)
{
    int e;
    fprintf(f, "  %-28s %13s %17s %13s\n", "estimator", "current [A]", "velocity [rad/s]", "angle [rad]");
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        const double *r = rmse + (size_t)e * TVM_NX;
        fprintf(f, "  %-28s %13.6g %17.6g %13.6g\n", sim_est_name((sim_est_t)e), r[0], r[1], r[2]);
    }
}

static void sim_json_rmse(FILE *f, const char *key, const double *rmse)
{
    int e;
    fprintf(f, "  \"%s\": {\n", key);
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        fprintf(f, "    \"%s\": {\"label\": \"%s\", \"current_A\": ", sim_est_id((sim_est_t)e), sim_est_name((sim_est_t)e));
        sim_jnum(f, rmse[(size_t)e * TVM_NX + 0]);
        fputs(", \"velocity_rad_s\": ", f);
        sim_jnum(f, rmse[(size_t)e * TVM_NX + 1]);
        fputs(", \"angle_rad\": ", f);
        sim_jnum(f, rmse[(size_t)e * TVM_NX + 2]);
        fprintf(f, "}%s\n", e + 1 < (int)SIM_EST_COUNT ? "," : "");
    }
    fputs("  },\n", f);
}

int sim_result_print(FILE *f, const sim_result_t *r)
{
    if (f == NULL || r == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "scenario %s, seed %llu, %.3f s simulated, %lu ticks, %lu scored (t >= %.2f s)\n",
            sim_scenario_name(r->scenario), (unsigned long long)r->seed, r->duration_s, (unsigned long)r->n_ticks,
            (unsigned long)r->n_scored, SIM_TRANSIENT_S);
    fputs("RMSE against the plant truth:\n", f);
    sim_print_rmse_rows(f, &r->rmse[0][0]);
    fprintf(f, "  %-28s %13.6g %17.6g %13.6g\n", "measurement bias (mean err)", r->meas_bias[0], r->meas_bias[1],
            r->meas_bias[2]);
    fprintf(f, "app filter consistency (one run: averages over its scored ticks; the bands are those of an\n"
               "average of N independent samples, so they are narrower than the truth for correlated errors;\n"
               "host_sim --mc N gives the per-tick band over N runs):\n");
    fprintf(f, "  NEES average %.4g (3 dof, N = %lu), 95%% band of the average [%.4g, %.4g]%s\n", r->nees_avg,
            (unsigned long)r->nees_n, r->nees_lo, r->nees_hi,
            sim_finite(r->nees_avg) ? (r->nees_avg >= r->nees_lo && r->nees_avg <= r->nees_hi
                                           ? "  inside"
                                           : (r->nees_avg < r->nees_lo ? "  BELOW (underconfident)" : "  ABOVE (overconfident)"))
                                    : "");
    fprintf(f, "  NIS  average %.4g (%.3g dof, N = %lu), 95%% band of the average [%.4g, %.4g]%s\n", r->nis_avg,
            r->nis_dof_avg, (unsigned long)r->nis_n, r->nis_lo, r->nis_hi,
            sim_finite(r->nis_avg) ? (r->nis_avg >= r->nis_lo && r->nis_avg <= r->nis_hi
                                          ? "  inside"
                                          : (r->nis_avg < r->nis_lo ? "  BELOW" : "  ABOVE"))
                                   : "");
    fprintf(f, "  NIS per channel (1 dof each, expected 1): current %.3g, velocity %.3g, angle %.3g\n",
            r->nis_ch_avg[EKF_CH_CURRENT], r->nis_ch_avg[EKF_CH_VELOCITY], r->nis_ch_avg[EKF_CH_ANGLE]);
    fprintf(f, "winding resistance at the end: estimate %.4g +- %.3g ohm (R + dR, ekf_resistance_error()), plant %.4g ohm\n",
            r->r_est_ohm, r->r_sigma_ohm, r->r_true_ohm);
    fprintf(f, "  the voltage equation's fit (volt_fit.h, last of %lu windows): R %.4g +- %.3g ohm, n Ke %.4g +- %.3g V s/rad, "
               "plant %.4g V s/rad; with an intercept, the current's offset %.3g +- %.3g A\n",
            (unsigned long)r->fit_windows, r->r_fit_ohm, r->r_fit_sigma_ohm, r->nke_fit_V_s, r->nke_fit_sigma_V_s,
            r->nke_true_V_s, r->i_off_fit_A, r->i_off_fit_sigma_A);
    if (isfinite(r->fit_base_r_ohm)) {
        fprintf(f, "  the fit's per-unit baseline (given or learned; diag.fit_base_r_ohm, diag.fit_base_nke_V_s): R %.6g ohm "
                   "at 20 degC, n Ke %.6g V s/rad\n",
                r->fit_base_r_ohm, r->fit_base_nke_V_s);
    }
    if (isfinite(r->r_20_ohm)) {
        fprintf(f, "  referred to 20 degC with the winding temperature the application was told: %.4g ohm, plant %.4g ohm\n",
                r->r_20_ohm, r->r_true_20_ohm);
    }
    fprintf(f, "friction level at the end: %.4g +- %.3g of the filter model's (1 + f, ekf_friction_error()), plant's "
               "Coulomb friction %.4g of it\n",
            r->friction_rel, r->friction_rel_sigma, r->friction_rel_true);
    fprintf(f, "spring preload at the end: %.4g +- %.3g of the filter model's (1 + m, ekf_preload_error()), plant's %.4g of it\n",
            r->preload_rel, r->preload_rel_sigma, r->preload_rel_true);
    fprintf(f, "stop onsets at the end: closed %.5f rad, open %.5f rad (online tracking, stop_track.h: %lu rest blocks "
               "accepted, %lu refused)\n",
            r->stop_onset_rad[0], r->stop_onset_rad[1], (unsigned long)r->stop_track_accepted,
            (unsigned long)r->stop_track_refused);
    fprintf(f, "contact law at the end: k %.4g N m/rad^e, exponent %.3g, damping ratio d/k %.4g s/rad, inflation's velocity "
               "coupling %.3g (impact learning, impact_learn.h: %lu impacts learned from, %lu with the stiffness, %lu abandoned; "
               "last rebound error / v_in %.3g)\n",
            r->contact_k, r->contact_exponent, r->contact_alpha_s_rad, r->contact_w_coupling, (unsigned long)r->impact_learned,
            (unsigned long)r->impact_k_updates, (unsigned long)r->impact_abandoned, r->impact_rebound_err_last);
    if (r->stop_learn_phase != (int)SL_IDLE) {
        fprintf(f, "stop learning (APP_MODE_STOP_LEARN): %s%s%s after %.3f s; closed %.5f rad, open %.5f rad; "
                   "largest speed near a stop %.3g rad/s\n",
                sl_phase_name((sl_phase_t)r->stop_learn_phase), r->stop_learn_error != 0 ? ": " : "",
                r->stop_learn_error != 0 ? sl_error_name((sl_error_t)r->stop_learn_error) : "", r->stop_learn_s,
                r->stop_learn_closed_rad, r->stop_learn_open_rad, r->stop_contact_speed_max);
        if (r->stop_learn_phase == (int)SL_DONE) {
            fprintf(f, "  learned contact law: onsets closed %.5f rad, open %.5f rad; k %.4g N m/rad^e, exponent %.3g\n",
                    r->stop_learn_onset_closed_rad, r->stop_learn_onset_open_rad, r->stop_learn_k, r->stop_learn_exponent);
        }
    }
    if (r->tracking.n_steps > 0u) {
        const sim_tracking_t *tk = &r->tracking;
        uint32_t k;
        fprintf(f, "closed-loop tracking of the plate angle (plant truth; sim_tracking.h):\n");
        fprintf(f, "  %-8s %-17s %13s %12s %16s\n", "t [s]", "target [rad]", "overshoot [%]", "settling [s]",
                "steady err [rad]");
        for (k = 0; k < tk->n_steps && k < SIM_TRK_MAX_STEPS; ++k) {
            const sim_trk_step_t *st = &tk->step[k];
            fprintf(f, "  %-8.3f %6.3f -> %6.3f   %13.2f %11.3f%s %16.3g\n", st->t_step_s, st->from_rad, st->to_rad,
                    st->overshoot_pct, st->settling_s, st->settled > 0.5 ? " " : "+", st->ss_error_rad);
        }
        fprintf(f, "  worst: overshoot %.2f %%, settling %.3f s, steady-state error %.3g rad; RMS tracking error %.3g rad\n"
                   "  (+: not settled within the segment)\n",
                tk->worst_overshoot_pct, tk->worst_settling_s, tk->worst_ss_error_rad, tk->rms_error_rad);
    } else if (r->tracking.n > 0u) {
        fprintf(f, "closed-loop tracking: RMS tracking error %.3g rad (no step of the target)\n", r->tracking.rms_error_rad);
    }
    fprintf(f, "events:\n");
    fprintf(f, "  faults latched 0x%02lx (%lu ticks with a fault", (unsigned long)r->faults, (unsigned long)r->fault_ticks);
    if (sim_finite(r->first_fault_t_s)) {
        fprintf(f, ", first at %.3f s", r->first_fault_t_s);
    }
    fprintf(f, "), EKF rejections %lu, missing samples %lu, HAL errors %lu\n", (unsigned long)r->ekf_rejections,
            (unsigned long)r->missing_samples, (unsigned long)r->hal_errors);
    fprintf(f, "  divergence-guard resets: paper as printed %lu, eq.12 predict %lu, eq.12 + exact Jac. %lu; "
               "paper set-up rejections %lu\n",
            (unsigned long)r->paper_printed_resets, (unsigned long)r->paper_eq12_resets,
            (unsigned long)r->paper_eq12x_resets, (unsigned long)r->paper_setup_rejections);
    {
        int k;
        int any = 0;
        fprintf(f, "diagnostic codes (firmware/diag/diag.h): %lu events, %lu lost", (unsigned long)r->dtc_events,
                (unsigned long)r->dtc_events_lost);
        for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
            const diag_dtc_info_t *i = diag_dtc_info((diag_dtc_t)k);
            if (sim_finite(r->dtc_confirm_t_s[k])) {
                fprintf(f, "%s %s (%s) confirmed at %.3f s%s", any ? "," : ";", i->code, i->fault_class, r->dtc_confirm_t_s[k],
                        (r->dtc_confirmed >> k) & 1u ? "" : ", healed since");
                any = 1;
            }
        }
        fprintf(f, "%s\n", any ? "" : "; none confirmed");
    }
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

int sim_result_json(FILE *f, const sim_result_t *r)
{
    if (f == NULL || r == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "{\n  \"scenario\": \"%s\",\n  \"seed\": %llu,\n  \"duration_s\": %.9g,\n  \"ticks\": %lu,\n",
            sim_scenario_name(r->scenario), (unsigned long long)r->seed, r->duration_s, (unsigned long)r->n_ticks);
    fprintf(f, "  \"transient_s\": %.9g,\n  \"scored_ticks\": %lu,\n", SIM_TRANSIENT_S, (unsigned long)r->n_scored);
    sim_json_rmse(f, "rmse", &r->rmse[0][0]);
    fputs("  \"measurement_bias\": {\"current_A\": ", f);
    sim_jnum(f, r->meas_bias[0]);
    fputs(", \"velocity_rad_s\": ", f);
    sim_jnum(f, r->meas_bias[1]);
    fputs(", \"angle_rad\": ", f);
    sim_jnum(f, r->meas_bias[2]);
    fputs("},\n  \"nees\": {\"average\": ", f);
    sim_jnum(f, r->nees_avg);
    fputs(", \"dof\": 3, \"band95\": [", f);
    sim_jnum(f, r->nees_lo);
    fputs(", ", f);
    sim_jnum(f, r->nees_hi);
    fprintf(f, "], \"n\": %lu},\n  \"nis\": {\"average\": ", (unsigned long)r->nees_n);
    sim_jnum(f, r->nis_avg);
    fputs(", \"dof\": ", f);
    sim_jnum(f, r->nis_dof_avg);
    fputs(", \"band95\": [", f);
    sim_jnum(f, r->nis_lo);
    fputs(", ", f);
    sim_jnum(f, r->nis_hi);
    fprintf(f, "], \"n\": %lu, \"per_channel\": {\"current\": ", (unsigned long)r->nis_n);
    sim_jnum(f, r->nis_ch_avg[EKF_CH_CURRENT]);
    fputs(", \"velocity\": ", f);
    sim_jnum(f, r->nis_ch_avg[EKF_CH_VELOCITY]);
    fputs(", \"angle\": ", f);
    sim_jnum(f, r->nis_ch_avg[EKF_CH_ANGLE]);
    fputs("}},\n  \"winding_resistance\": {\"estimate_ohm\": ", f);
    sim_jnum(f, r->r_est_ohm);
    fputs(", \"sigma_ohm\": ", f);
    sim_jnum(f, r->r_sigma_ohm);
    fputs(", \"plant_ohm\": ", f);
    sim_jnum(f, r->r_true_ohm);
    fputs(", \"estimate_20C_ohm\": ", f);
    sim_jnum(f, r->r_20_ohm);
    fputs(", \"plant_20C_ohm\": ", f);
    sim_jnum(f, r->r_true_20_ohm);
    {
        /* the voltage equation's fit (volt_fit.h) */
        const char *const keys[] = {"fit_ohm", "fit_sigma_ohm", "fit_nke_V_s_rad", "fit_nke_sigma_V_s_rad", "plant_nke_V_s_rad",
                                    "fit_current_offset_A", "fit_current_offset_sigma_A", "fit_base_20C_ohm",
                                    "fit_base_nke_V_s_rad"};
        const double vals[] = {r->r_fit_ohm, r->r_fit_sigma_ohm, r->nke_fit_V_s, r->nke_fit_sigma_V_s, r->nke_true_V_s,
                               r->i_off_fit_A, r->i_off_fit_sigma_A, r->fit_base_r_ohm, r->fit_base_nke_V_s};
        size_t k;
        for (k = 0; k < sizeof vals / sizeof vals[0]; ++k) {
            fprintf(f, ", \"%s\": ", keys[k]);
            sim_jnum(f, vals[k]);
        }
    }
    fprintf(f, ", \"fit_windows\": %lu", (unsigned long)r->fit_windows);
    fputs("},\n  \"friction_level\": {\"estimate_rel\": ", f);
    sim_jnum(f, r->friction_rel);
    fputs(", \"sigma_rel\": ", f);
    sim_jnum(f, r->friction_rel_sigma);
    fputs(", \"plant_coulomb_rel\": ", f);
    sim_jnum(f, r->friction_rel_true);
    fputs("},\n  \"spring_preload\": {\"estimate_rel\": ", f);
    sim_jnum(f, r->preload_rel);
    fputs(", \"sigma_rel\": ", f);
    sim_jnum(f, r->preload_rel_sigma);
    fputs(", \"plant_rel\": ", f);
    sim_jnum(f, r->preload_rel_true);
    fputs("},\n  \"stop_tracking\": {\"closed_rad\": ", f);
    sim_jnum(f, r->stop_onset_rad[0]);
    fputs(", \"open_rad\": ", f);
    sim_jnum(f, r->stop_onset_rad[1]);
    fprintf(f, ", \"accepted\": %lu, \"refused\": %lu},\n", (unsigned long)r->stop_track_accepted,
            (unsigned long)r->stop_track_refused);
    fputs("  \"contact_law\": {\"k\": ", f);
    sim_jnum(f, r->contact_k);
    fputs(", \"exponent\": ", f);
    sim_jnum(f, r->contact_exponent);
    fputs(", \"alpha_s_rad\": ", f);
    sim_jnum(f, r->contact_alpha_s_rad);
    fputs(", \"w_coupling\": ", f);
    sim_jnum(f, r->contact_w_coupling);
    fputs(", \"restitution_last\": ", f);
    sim_jnum(f, r->impact_rebound_err_last);
    fprintf(f, ", \"impacts_learned\": %lu, \"k_updates\": %lu, \"abandoned\": %lu},\n", (unsigned long)r->impact_learned,
            (unsigned long)r->impact_k_updates, (unsigned long)r->impact_abandoned);
    if (r->tracking.n > 0u) {
        fprintf(f, "  \"tracking\": {\"steps\": %lu, \"worst_overshoot_pct\": ", (unsigned long)r->tracking.n_steps);
        sim_jnum(f, r->tracking.worst_overshoot_pct);
        fputs(", \"worst_settling_s\": ", f);
        sim_jnum(f, r->tracking.worst_settling_s);
        fputs(", \"worst_steady_state_error_rad\": ", f);
        sim_jnum(f, r->tracking.worst_ss_error_rad);
        fputs(", \"rms_error_rad\": ", f);
        sim_jnum(f, r->tracking.rms_error_rad);
        fputs("},\n", f);
    }
    fprintf(f, "  \"faults\": %lu,\n  \"fault_ticks\": %lu,\n  \"first_fault_t_s\": ", (unsigned long)r->faults,
            (unsigned long)r->fault_ticks);
    sim_jnum(f, r->first_fault_t_s);
    fprintf(f, ",\n  \"ekf_rejections\": %lu,\n  \"missing_samples\": %lu,\n  \"hal_errors\": %lu,\n",
            (unsigned long)r->ekf_rejections, (unsigned long)r->missing_samples, (unsigned long)r->hal_errors);
    fprintf(f,
            "  \"paper_setup_rejections\": %lu,\n  \"paper_printed_resets\": %lu,\n  \"paper_eq12_resets\": %lu,\n"
            "  \"paper_eq12_exact_resets\": %lu\n}\n",
            (unsigned long)r->paper_setup_rejections, (unsigned long)r->paper_printed_resets,
            (unsigned long)r->paper_eq12_resets, (unsigned long)r->paper_eq12x_resets);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

int sim_mc_print(FILE *f, const sim_mc_result_t *m)
{
    if (f == NULL || m == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "Monte Carlo: scenario %s, %lu seeds from %llu, %.3f s each, %lu scored ticks per run (t >= %.2f s)\n",
            sim_scenario_name(m->scenario), (unsigned long)m->n_seeds, (unsigned long long)m->first_seed,
            m->duration_s, (unsigned long)m->n_ticks_scored, SIM_TRANSIENT_S);
    fputs("mean RMSE over seeds:\n", f);
    sim_print_rmse_rows(f, &m->rmse_mean[0][0]);
    fputs("largest RMSE over seeds:\n", f);
    sim_print_rmse_rows(f, &m->rmse_max[0][0]);
    fprintf(f, "app filter consistency:\n");
    fprintf(f, "  ANEES %.4g (3 dof); 95%% band of the %lu-run average per tick [%.4g, %.4g]; ticks inside: %.1f %%\n",
            m->anees, (unsigned long)m->n_seeds, m->band_lo, m->band_hi, 100.0 * m->frac_ticks_in_band);
    fprintf(f, "  (band of the grand average if all samples were independent: [%.4g, %.4g])\n", m->anees_lo,
            m->anees_hi);
    fprintf(f, "  ANIS %.4g (%.3g dof)\n", m->anis, m->nis_dof_avg);
    fprintf(f, "events: runs with faults %lu, EKF rejections %lu, missing samples %lu, paper-as-printed resets %lu\n",
            (unsigned long)m->runs_with_faults, (unsigned long)m->ekf_rejections, (unsigned long)m->missing_samples,
            (unsigned long)m->paper_printed_resets);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

int sim_mc_json(FILE *f, const sim_mc_result_t *m)
{
    if (f == NULL || m == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "{\n  \"scenario\": \"%s\",\n  \"seeds\": %lu,\n  \"first_seed\": %llu,\n  \"duration_s\": %.9g,\n",
            sim_scenario_name(m->scenario), (unsigned long)m->n_seeds, (unsigned long long)m->first_seed, m->duration_s);
    fprintf(f, "  \"transient_s\": %.9g,\n  \"scored_ticks_per_run\": %lu,\n", SIM_TRANSIENT_S,
            (unsigned long)m->n_ticks_scored);
    sim_json_rmse(f, "rmse_mean", &m->rmse_mean[0][0]);
    sim_json_rmse(f, "rmse_max", &m->rmse_max[0][0]);
    fputs("  \"anees\": ", f);
    sim_jnum(f, m->anees);
    fputs(",\n  \"band95_m_run_average\": [", f);
    sim_jnum(f, m->band_lo);
    fputs(", ", f);
    sim_jnum(f, m->band_hi);
    fputs("],\n  \"fraction_ticks_in_band\": ", f);
    sim_jnum(f, m->frac_ticks_in_band);
    fputs(",\n  \"band95_grand_average\": [", f);
    sim_jnum(f, m->anees_lo);
    fputs(", ", f);
    sim_jnum(f, m->anees_hi);
    fputs("],\n  \"anis\": ", f);
    sim_jnum(f, m->anis);
    fputs(",\n  \"nis_dof\": ", f);
    sim_jnum(f, m->nis_dof_avg);
    fprintf(f, ",\n  \"runs_with_faults\": %lu,\n  \"ekf_rejections\": %lu,\n  \"missing_samples\": %lu,\n",
            (unsigned long)m->runs_with_faults, (unsigned long)m->ekf_rejections, (unsigned long)m->missing_samples);
    fprintf(f, "  \"paper_printed_resets\": %lu\n}\n", (unsigned long)m->paper_printed_resets);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}
