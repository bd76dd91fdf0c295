/* dm_sbuf.h — a growing string for writers of JSON text that must come out byte for byte
 * the same (profile documents): printf-style appends, numbers with 17 significant digits
 * (they read back exactly), non-finite numbers as null, strings escaped by cJSON.
 * An allocation failure leaves the buffer failed: later appends do nothing and the
 * writer checks `failed` once at the end. Free s with free(). */
#ifndef DM_SBUF_H
#define DM_SBUF_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct dm_sbuf {
    char *s; /* NUL-terminated once anything was appended; NULL before */
    size_t len, cap;
    int failed;
} dm_sbuf;

void dm_sbuf_put(dm_sbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void dm_sbuf_num(dm_sbuf *b, double v);          /* %.17g, or null when not finite */
void dm_sbuf_rgb(dm_sbuf *b, const double v[3]); /* [r, g, b] */
void dm_sbuf_str(dm_sbuf *b, const char *s);     /* a JSON string; NULL writes "" */

#ifdef __cplusplus
}
#endif
#endif
