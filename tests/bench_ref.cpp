/**
 * @file bench_ref.cpp
 * @brief Instruction-count benchmark of the Eigen reference filter (tests/ref/tv_ref.hpp), to be
 *        run under `valgrind --tool=callgrind`. Not a test.
 *
 * Usage: bench_ref <mode> <steps>
 *   mode "filter": per step only the filter arithmetic: P = F P F^T + Q with a FIXED F (the
 *                  AutoDiff Jacobian at one mid-stroke state, computed once before the loop),
 *                  x = F x, then the correction (current + angle, sequential Joseph updates) and
 *                  the variance bounds. No model evaluation in the loop.
 *   mode "full":   per step the complete reference EKF: predict with the model map
 *                  (N = 10 sub-steps) and its AutoDiff Jacobian, then the same correction.
 * Set-up: ekf default configuration (current + angle). Data: the paper's experiment
 * (u = 12 V sin(2 pi 5 t), 1 kHz); one 200-sample period of truth-plus-noise is precomputed
 * AFTER 1 s of settling, before the loop, and replayed cyclically, so the loop does no data
 * generation and its cost per step does not depend on <steps>.
 *
 * The loops are the extern "C" functions bench_loop_filter / bench_loop_full (never inlined):
 * count per step either with `--toggle-collect=bench_loop_*` or by differencing two runs with
 * different <steps> (the set-up outside the loop is the same for every <steps>).
 * Prints a checksum of the estimates so that nothing is optimised away.
 */
#include "ref/tv_ref.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

const double kPi = 3.14159265358979323846;
const int kPeriod = 200; /* samples per period of the 5 Hz sine at 1 kHz */

struct Sample {
    double u;           /* input applied over the step leading to z */
    Eigen::Vector3d z;  /* measurement after that step */
};

/** Precompute one period of (u, z) after 1 s of settling from rest. Deterministic noise (LCG). */
std::vector<Sample> make_table(const tvref::Params& p)
{
    uint64_t s = 0x0123456789ABCDEFULL;
    auto uniform = [&s] {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
    };
    auto normal = [&uniform] {
        const double u1 = 1.0 - uniform(), u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    };
    const Eigen::Vector3d sigma(0.01, 1.0, 1e-4);
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    std::vector<Sample> t;
    for (int k = 0; k < 1000 + kPeriod; ++k) {
        const double u = 12.0 * std::sin(2.0 * kPi * 5.0 * k * p.Ts_s);
        x = tvref::step<double>(p, x, u);
        if (k >= 1000) {
            Sample smp;
            smp.u = u;
            for (int j = 0; j < 3; ++j) {
                smp.z(j) = x(j) + sigma(j) * normal();
            }
            t.push_back(smp);
        }
    }
    return t;
}

double checksum_of(const tvref::Ekf& f, const tvref::Innov& in)
{
    return f.x().sum() + f.P().trace() + in.nis_total;
}

} // namespace

/** The filter-arithmetic loop: fixed F, no model. Returns a checksum. */
extern "C" __attribute__((noinline)) double bench_loop_filter(tvref::Ekf* f, const Eigen::Matrix3d* F,
                                                              const Sample* table, long steps)
{
    double sum = 0.0;
    for (long k = 0; k < steps; ++k) {
        const Sample& smp = table[k % kPeriod];
        f->predict_with(*F, *F * f->x());
        sum += checksum_of(*f, f->correct(smp.z));
    }
    return sum;
}

/** The full reference EKF loop: model, AD Jacobian, covariance, correction. Returns a checksum. */
extern "C" __attribute__((noinline)) double bench_loop_full(tvref::Ekf* f, const Sample* table,
                                                            long steps)
{
    double sum = 0.0;
    for (long k = 0; k < steps; ++k) {
        const Sample& smp = table[k % kPeriod];
        f->predict(smp.u);
        sum += checksum_of(*f, f->correct(smp.z));
    }
    return sum;
}

int main(int argc, char** argv)
{
    const bool ok_args = argc == 3 && (std::strcmp(argv[1], "filter") == 0 ||
                                       std::strcmp(argv[1], "full") == 0);
    char* end = nullptr;
    const long steps = ok_args ? std::strtol(argv[2], &end, 10) : -1;
    if (!ok_args || end == argv[2] || *end != '\0' || steps < 0) {
        fprintf(stderr, "usage: %s <filter|full> <steps>\n", argc > 0 ? argv[0] : "bench_ref");
        return 2;
    }
    const tvref::Params p;
    const std::vector<Sample> table = make_table(p);
    tvref::Ekf f(p, tvref::config_default(p, tvref::Setup::CurrentAngle));

    double sum;
    if (std::strcmp(argv[1], "filter") == 0) {
        /* a mid-stroke, sliding state: a representative, dense Jacobian */
        const Eigen::Matrix3d F = tvref::jacobian_ad(p, Eigen::Vector3d(1.0, 10.0, 0.6), 6.0);
        sum = bench_loop_filter(&f, &F, table.data(), steps);
    } else {
        sum = bench_loop_full(&f, table.data(), steps);
    }
    printf("mode %s steps %ld checksum %.17g\n", argv[1], steps, sum);
    return 0;
}
