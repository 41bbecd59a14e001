/**
 * @file tv_status.h
 * @brief The one project-wide error enum. Functions that can fail return int: 0 on success,
 *        one of these negative values on error.
 */
#ifndef TV_STATUS_H
#define TV_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

/** Return codes (0 ok, negative error). */
typedef enum {
    TV_OK = 0,
    TV_ERR_NULL = -1,      /**< a required pointer argument was NULL (caller's bug) */
    TV_ERR_NONFINITE = -2, /**< an input was NaN or infinite; nothing was changed */
    TV_ERR_RANGE = -3,     /**< an input was finite but outside its documented range; nothing changed */
    TV_ERR_CONFIG = -4,    /**< a parameter or configuration value is invalid */
    TV_ERR_NUMERIC = -5,   /**< a computed result was non-finite or not positive where it must be;
                                state left as it was before the call */
    TV_ERR_FORMAT = -6,    /**< malformed external data (log line, frame, file) */
    TV_ERR_IO = -7,        /**< an I/O operation failed */
    TV_ERR_FAULT = -8      /**< the application is latched in its safe state */
} tv_status_t;

/** Short constant English name of a status code ("ok", "non-finite input", ...). */
const char *tv_status_str(int status);

#ifdef __cplusplus
}
#endif

#endif /* TV_STATUS_H */
