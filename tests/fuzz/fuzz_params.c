/**
 * @file fuzz_params.c
 * @brief libFuzzer target of the parameter-file parser (host_sim/replay/params.h) and of applying the
 *        result to the default configuration and initialising the application with it.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "params.h"

static params_t s_p;
static app_t s_app;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[PARAMS_MSG_MAX];
    app_config_t cfg;
    params_init(&s_p, "fuzz");
    err[0] = '\0';
    if (params_parse_text(&s_p, (const char *)data, size, err, sizeof err) != 0) {
        if (memchr(err, '\0', sizeof err) == NULL || err[0] == '\0') {
            abort(); /* every error has a message */
        }
        return 0;
    }
    app_config_default(&cfg);
    if (params_apply(&s_p, &cfg, err, sizeof err) == 0) {
        (void)app_init(&s_app, &cfg); /* may refuse, must not crash */
    }
    return 0;
}
