/**
 * @file sim_stats.c
 * @brief Statistics of the simulation: normal and chi-square quantiles, Mahalanobis distance.
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"
#include "tv_status.h"

/* ------------------------------------------------------------------------------------------ */
/* Statistics                                                                                  */
/* ------------------------------------------------------------------------------------------ */

int sim_finite(double v)
{
    return v == v && v - v == 0.0;
}

double sim_normal_quantile(double p)
{
    /* P. J. Acklam's rational approximation (relative error 1.15e-9), then one Halley step
     * on erfc for full double accuracy. */
    static const double a[6] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[5] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                6.680131188771972e+01,  -1.328068155288572e+01};
    static const double c[6] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[4] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                3.754408661907416e+00};
    const double p_low = 0.02425;
    double q;
    double r;
    double x;
    if (!(p > 0.0 && p < 1.0)) {
        return SIM_NAN;
    }
    if (p < p_low) {
        q = sqrt(-2.0 * log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    } else if (p <= 1.0 - p_low) {
        q = p - 0.5;
        r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
    } else {
        q = sqrt(-2.0 * log(1.0 - p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    }
    {
        const double e = 0.5 * erfc(-x / sqrt(2.0)) - p;
        const double u = e * sqrt(2.0 * 3.14159265358979323846) * exp(x * x / 2.0);
        x = x - u / (1.0 + x * u / 2.0);
    }
    return x;
}

double sim_chi2_quantile(double p, double dof)
{
    double z;
    double k;
    double t;
    if (!(p > 0.0 && p < 1.0) || !(dof > 0.0) || !sim_finite(dof)) {
        return SIM_NAN;
    }
    z = sim_normal_quantile(p);
    k = 2.0 / (9.0 * dof);
    t = 1.0 - k + z * sqrt(k);
    return t > 0.0 ? dof * t * t * t : 0.0;
}

/* e^T P^-1 e by Cholesky of the 3x3 P (double); NaN when P is not positive definite. */
double sim_mahalanobis3(double P[TVM_NX][TVM_NX], const double e[TVM_NX])
{
    double Lc[TVM_NX][TVM_NX];
    double y[TVM_NX] = {0.0, 0.0, 0.0};
    double s = 0.0;
    int i;
    int j;
    int k;
    memset(Lc, 0, sizeof Lc);
    for (i = 0; i < TVM_NX; ++i) {
        for (j = 0; j <= i; ++j) {
            double v = 0.5 * (P[i][j] + P[j][i]);
            for (k = 0; k < j; ++k) {
                v -= Lc[i][k] * Lc[j][k];
            }
            if (i == j) {
                if (!(v > 0.0)) {
                    return SIM_NAN;
                }
                Lc[i][i] = sqrt(v);
            } else {
                Lc[i][j] = v / Lc[j][j];
            }
        }
    }
    for (i = 0; i < TVM_NX; ++i) {
        double v = e[i];
        for (k = 0; k < i; ++k) {
            v -= Lc[i][k] * y[k];
        }
        y[i] = v / Lc[i][i];
        s += y[i] * y[i];
    }
    return s;
}
