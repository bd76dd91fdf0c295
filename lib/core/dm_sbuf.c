/* dm_sbuf.c — the growing string of dm_sbuf.h. */
#include "core/dm_sbuf.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include <cJSON.h>

void dm_sbuf_put(dm_sbuf *b, const char *fmt, ...)
{
    if (b->failed) return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->failed = 1;
            return;
        }
        if (b->s && b->len + (size_t)n < b->cap) {
            b->len += (size_t)n;
            return;
        }
        size_t cap = b->cap ? b->cap : 1024;
        while (cap <= b->len + (size_t)n) cap *= 2;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->failed = 1;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

void dm_sbuf_num(dm_sbuf *b, double v)
{
    if (isfinite(v))
        dm_sbuf_put(b, "%.17g", v);
    else
        dm_sbuf_put(b, "null");
}

void dm_sbuf_rgb(dm_sbuf *b, const double v[3])
{
    dm_sbuf_put(b, "[");
    for (int c = 0; c < 3; ++c) {
        if (c) dm_sbuf_put(b, ", ");
        dm_sbuf_num(b, v[c]);
    }
    dm_sbuf_put(b, "]");
}

void dm_sbuf_str(dm_sbuf *b, const char *s)
{
    cJSON *j = cJSON_CreateString(s ? s : "");
    char *t = j ? cJSON_PrintUnformatted(j) : NULL;
    if (t)
        dm_sbuf_put(b, "%s", t);
    else
        b->failed = 1;
    cJSON_free(t);
    cJSON_Delete(j);
}
