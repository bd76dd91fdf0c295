/* pack_edit.h — edits a valid pack's values in memory as a bug or an attacker would, then
 * makes every checksum right again (each blob's "xxh3" and the header's), so that only the
 * reader's semantic checks (pack/dm_pack_semantic.h) stand between the edit and a renderer.
 * Buffers are 64-byte aligned (test_pack_load) so dm_pack_open_memory takes them. */
#ifndef TEST_PACK_EDIT_H
#define TEST_PACK_EDIT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/dm_hash.h"
#include "pack/dm_pack.h"

/* The manifest's size, from the header (dm_pack_header_decode: the reader's own decoding). */
static inline uint64_t test_pack_manifest_size(const uint8_t *buf)
{
    dm_pack_header h;
    dm_pack_header_decode(buf, &h);
    return h.manifest_size;
}
/* The manifest as a NUL-terminated copy (free it). */
static inline char *test_pack_manifest(const uint8_t *buf)
{
    uint64_t n = test_pack_manifest_size(buf);
    char *m = malloc(n + 1);
    if (m) memcpy(m, buf + DM_PACK_HEADER_SIZE, n), m[n] = '\0';
    return m;
}

/* Offset and size of entry `name`'s blob; false when there is none. */
static inline bool test_pack_blob(const uint8_t *buf, const char *name, uint64_t *offset, uint64_t *size)
{
    char *m = test_pack_manifest(buf);
    cJSON *root = m ? cJSON_Parse(m) : NULL;
    bool found = false;
    const cJSON *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(root, "entries"))
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(e, "name");
        if (!cJSON_IsString(n) || strcmp(n->valuestring, name) != 0) continue;
        *offset = (uint64_t)cJSON_GetObjectItemCaseSensitive(e, "offset")->valuedouble;
        *size = (uint64_t)cJSON_GetObjectItemCaseSensitive(e, "size")->valuedouble;
        found = true;
    }
    cJSON_Delete(root);
    free(m);
    return found;
}

/* Rewrites every entry's "xxh3" to the hash of its bytes (within size), then the header's. */
static inline void test_pack_fix_checksums(uint8_t *buf, size_t size)
{
    uint64_t msize = test_pack_manifest_size(buf);
    if (msize > size - DM_PACK_HEADER_SIZE) return;
    char *m = test_pack_manifest(buf), *text = (char *)buf + DM_PACK_HEADER_SIZE;
    cJSON *root = m ? cJSON_Parse(m) : NULL;
    const cJSON *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(root, "entries"))
    {
        const cJSON *off = cJSON_GetObjectItemCaseSensitive(e, "offset");
        const cJSON *sz = cJSON_GetObjectItemCaseSensitive(e, "size"), *x = cJSON_GetObjectItemCaseSensitive(e, "xxh3");
        if (!cJSON_IsNumber(off) || !cJSON_IsNumber(sz) || !cJSON_IsString(x) || strlen(x->valuestring) != 16) continue;
        uint64_t o = (uint64_t)off->valuedouble, n = (uint64_t)sz->valuedouble;
        if (o > size || n > size - o) continue;
        char now[17];
        dm_pack_hex64(dm_hash64(buf + o, (size_t)n), now);
        char *at = strstr(m, x->valuestring); /* in the copy: the manifest in buf has no NUL */
        if (at) memcpy(text + (at - m), now, 16), memcpy(at, now, 16);
    }
    cJSON_Delete(root);
    free(m);
    uint64_t sum = dm_pack_header_checksum(buf, buf + DM_PACK_HEADER_SIZE, (size_t)msize);
    for (int k = 0; k < 8; ++k) buf[56 + k] = (uint8_t)(sum >> (8 * k));
}

/* Sets `count` floats of entry `name`, the first at float index `first`, then every `step`
 * (1 for a run), to `value`; fixes the checksums. False when the entry or a float is absent. */
static inline bool test_pack_set_floats(uint8_t *buf, size_t size, const char *name, uint64_t first, uint64_t count,
                                        uint64_t step, float value)
{
    uint64_t off, bytes;
    if (!test_pack_blob(buf, name, &off, &bytes)) return false;
    for (uint64_t i = 0; i < count; ++i) {
        uint64_t at = (first + i * step) * 4;
        if (at + 4 > bytes) return false;
        memcpy(buf + off + at, &value, 4);
    }
    test_pack_fix_checksums(buf, size);
    return true;
}

/* Replaces the first `from` in the manifest by `to`, keeping the manifest's size: a longer
 * `to` takes whitespace between tokens elsewhere (tabs and newlines are never inside JSON
 * strings), a shorter one leaves spaces. Fixes the header checksum. */
static inline bool test_pack_replace_manifest(uint8_t *buf, size_t size, const char *from, const char *to)
{
    char *m = test_pack_manifest(buf);
    char *at = m ? strstr(m, from) : NULL;
    if (!at) return free(m), false;
    size_t msize = strlen(m), nf = strlen(from), nt = strlen(to), pos = (size_t)(at - m);
    char *out = malloc(msize + nt + 1);
    size_t k = 0, extra = nt > nf ? nt - nf : 0;
    for (size_t i = 0; i < msize;) {
        if (i == pos) {
            memcpy(out + k, to, nt), k += nt, i += nf;
            for (size_t pad = nt; pad < nf; ++pad) out[k++] = ' ';
            continue;
        }
        if (extra && (m[i] == '\t' || m[i] == '\n')) {
            --extra, ++i;
            continue;
        }
        out[k++] = m[i++];
    }
    bool ok = extra == 0 && k == msize;
    if (ok) memcpy(buf + DM_PACK_HEADER_SIZE, out, msize);
    free(out);
    free(m);
    if (ok) test_pack_fix_checksums(buf, size);
    return ok;
}

/* A pack file in 64-byte aligned memory (free it); NULL when it cannot be read. */
static inline uint8_t *test_pack_load(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *buf = n > 0 ? aligned_alloc(64, ((size_t)n + 63) / 64 * 64) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) free(buf), buf = NULL;
    fclose(f);
    *size = (size_t)n;
    return buf;
}

static inline bool test_pack_save(const char *path, const uint8_t *buf, size_t size)
{
    FILE *f = fopen(path, "wb");
    bool ok = f && fwrite(buf, 1, size, f) == size;
    if (f) ok = fclose(f) == 0 && ok;
    return ok;
}

#endif
