/**
 * @file tvlog_gen.h
 * @brief The replay input stream's scenario: the host_sim plant (double precision) in closed
 *        loop with the float application, through every mode, a gap, a driver fault, a track
 *        fault and fault clearing. Built on the host (m4f_replay_host gen) and into the QEMU
 *        benchmark image (qemu_bench gen): same scenario, each side's own arithmetic.
 *
 * Timeline, as a fraction of the run (6000 steps: the replay test; shorter for the benchmark):
 *   0     sine (default, 12 V 5 Hz)         25.0 %  steps (square wave)
 *   38.3 % chirp 5 -> 20 Hz                  51.7 %  position, target 0.3 rad
 *   60.0 % position, target 0.9 rad          63.3 %  3 samples lost (a gap, predicted across)
 *   68.3 % driver fault input for 1 sample   71.7 %  faults cleared
 *   76.7 % track 1 open (0 counts) 10 samples 80.0 % faults cleared
 *   83.3 % off                               88.3 %  sine again
 */
#ifndef TVLOG_GEN_H
#define TVLOG_GEN_H

#include <stdint.h>

#include "app.h"
#include "plant.h"
#include "tvlog.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Generator state. Large: allocate statically. */
typedef struct {
    plant_t plant;
    app_t app;
    uint32_t k;     /**< next step */
    uint32_t steps; /**< steps in the run */
} tvlog_gen_t;

/** Start a run of steps (>= 100) milliseconds. @return 0, or a negative tv_status_t. */
int tvlog_gen_init(tvlog_gen_t *g, uint32_t steps, uint64_t seed);

/**
 * Advance one millisecond.
 * @return 1: *rec is this step's input record; 0: the sample was lost (no record, the plant
 *         still advanced); -1: the run is complete; < -1: the plant failed.
 */
int tvlog_gen_next(tvlog_gen_t *g, tvlog_in_t *rec);

#ifdef __cplusplus
}
#endif

#endif /* TVLOG_GEN_H */
