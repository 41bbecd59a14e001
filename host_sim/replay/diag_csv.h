/**
 * @file diag_csv.h
 * @brief The diagnostic-event CSV of host_sim and replay (--events FILE): a header line
 *        "t_us,status,fault_class,dtc" and one line per event of firmware/diag/diag.h, e.g.
 *        "1019000,confirmed,tps1_fault,P0121" (status pending, confirmed or healed).
 */
#ifndef DIAG_CSV_H
#define DIAG_CSV_H

#include <stdio.h>

#include "diag.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Write the header line. @return TV_OK; TV_ERR_NULL; TV_ERR_IO. */
int diag_csv_header(FILE *f);

/** Write one event. @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (unknown code); TV_ERR_IO. */
int diag_csv_event(FILE *f, const diag_event_t *ev);

#ifdef __cplusplus
}
#endif

#endif /* DIAG_CSV_H */
