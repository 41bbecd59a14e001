/**
 * @file diag_csv.c
 * @brief The diagnostic-event CSV (see diag_csv.h).
 */
#include "diag_csv.h"

#include "tv_status.h"

int diag_csv_header(FILE *f)
{
    if (f == NULL) {
        return TV_ERR_NULL;
    }
    return fputs("t_us,status,fault_class,dtc\n", f) < 0 ? TV_ERR_IO : TV_OK;
}

int diag_csv_event(FILE *f, const diag_event_t *ev)
{
    const diag_dtc_info_t *i;
    if (f == NULL || ev == NULL) {
        return TV_ERR_NULL;
    }
    i = diag_dtc_info(ev->dtc);
    if (i == NULL) {
        return TV_ERR_RANGE;
    }
    return fprintf(f, "%llu,%s,%s,%s\n", (unsigned long long)ev->t_us, diag_event_name(ev->kind), i->fault_class, i->code) < 0
               ? TV_ERR_IO
               : TV_OK;
}
