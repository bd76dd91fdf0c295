#include "core/dm_result.h"

#include <stdarg.h>
#include <stdio.h>

static const char *const names[] = {
#define DM_X_NAME(name, msg) #name,
    DM_RESULT_TABLE(DM_X_NAME)
#undef DM_X_NAME
};

static const char *const messages[] = {
#define DM_X_MSG(name, msg) msg,
    DM_RESULT_TABLE(DM_X_MSG)
#undef DM_X_MSG
};

const char *dm_result_name(dm_result r)
{
    return (r >= 0 && r < DM_RESULT_COUNT) ? names[r] : "DM_UNKNOWN";
}

const char *dm_result_message(dm_result r)
{
    return (r >= 0 && r < DM_RESULT_COUNT) ? messages[r] : "unknown result";
}

dm_result dm_fail(dm_error *err, dm_result code, const char *fmt, ...)
{
    if (err) {
        err->code = code;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->detail, sizeof err->detail, fmt, ap);
        va_end(ap);
    }
    return code;
}
