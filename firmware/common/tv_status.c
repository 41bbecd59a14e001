#include "tv_status.h"

const char *tv_status_str(int status)
{
    switch (status) {
    case TV_OK: return "ok";
    case TV_ERR_NULL: return "null pointer argument";
    case TV_ERR_NONFINITE: return "non-finite input";
    case TV_ERR_RANGE: return "input out of range";
    case TV_ERR_CONFIG: return "invalid configuration";
    case TV_ERR_NUMERIC: return "numerical failure";
    case TV_ERR_FORMAT: return "malformed data";
    case TV_ERR_IO: return "i/o error";
    case TV_ERR_FAULT: return "latched fault";
    default: return "unknown status";
    }
}
