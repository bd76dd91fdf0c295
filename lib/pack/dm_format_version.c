/* dm_format_version.c — the format and version a file declares, and this dermis's verdict
 * (pack/dm_format_version.h): a pack's header (and manifest "version"), a scene's top level. */
#include "pack/dm_format_version.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cJSON.h>

#include "core/dm_input.h"
#include "pack/dm_pack_format.h"
#include "core/dm_scene.h"

/* `size` bytes of f from `offset` into a malloc'd NUL-terminated buffer; *got the bytes read
 * (fewer at the end of the file). */
static dm_result read_part(FILE *f, const char *path, long offset, size_t size, char **out, size_t *got,
                           dm_error *err)
{
    *out = NULL;
    *got = 0;
    char *buf = malloc(size + 1);
    if (!buf) return dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", path, size);
    if (fseek(f, offset, SEEK_SET) != 0) {
        free(buf);
        return dm_fail(err, DM_ERR_FILE_READ, "%s: %s", path, strerror(errno));
    }
    size_t n = fread(buf, 1, size, f);
    if (ferror(f)) {
        free(buf);
        return dm_fail(err, DM_ERR_FILE_READ, "%s: read error", path);
    }
    buf[n] = '\0';
    *out = buf;
    *got = n;
    return DM_OK;
}

/* A JSON "version": an integer, else DM_ERR_FORMAT naming where. */
static dm_result json_version(const cJSON *v, const char *where, int64_t *out, dm_error *err)
{
    if (!cJSON_IsNumber(v) || v->valuedouble != floor(v->valuedouble) || !(fabs(v->valuedouble) < 1e18)) {
        char *text = v ? cJSON_PrintUnformatted(v) : NULL;
        dm_result r = dm_fail(err, DM_ERR_FORMAT, "%s: \"version\" %s, expected an integer", where,
                              text ? text : "missing");
        cJSON_free(text);
        return r;
    }
    *out = (int64_t)v->valuedouble;
    return DM_OK;
}

/* The header's version; when it is DM_PACK_VERSION, the manifest's (the one the reader
 * checks next). A later version's layout beyond the header is unknown: not read. */
static dm_result pack_version(FILE *f, const char *path, const uint8_t *head, size_t got, dm_format_version *out,
                              dm_error *err)
{
    if (got < DM_PACK_HEADER_SIZE)
        return dm_fail(err, DM_ERR_FORMAT, "%s: %zu bytes, expected at least the %d-byte pack header (truncated?)",
                       path, got, DM_PACK_HEADER_SIZE);
    dm_pack_header h;
    dm_pack_header_decode(head, &h);
    out->version = h.version;
    if (h.version != DM_PACK_VERSION) return DM_OK;
    if (h.manifest_offset != DM_PACK_HEADER_SIZE || h.manifest_size < 2 || h.manifest_size > DM_PACK_MANIFEST_MAX)
        return dm_fail(err, DM_ERR_FORMAT,
                       "%s: manifest at %" PRIu64 ", %" PRIu64 " bytes, expected at %d, 2..%d bytes (corrupt: "
                       "dermis-check FILE says more)",
                       path, h.manifest_offset, h.manifest_size, DM_PACK_HEADER_SIZE, DM_PACK_MANIFEST_MAX);
    char *text;
    size_t n;
    dm_result r = read_part(f, path, DM_PACK_HEADER_SIZE, (size_t)h.manifest_size, &text, &n, err);
    if (r != DM_OK) return r;
    char where[1200];
    snprintf(where, sizeof where, "%s: manifest", path);
    cJSON *root = n == h.manifest_size ? cJSON_ParseWithLength(text, n) : NULL;
    const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(root, "format");
    if (n != h.manifest_size)
        r = dm_fail(err, DM_ERR_FORMAT, "%s: %zu of %" PRIu64 " bytes (truncated)", where, n, h.manifest_size);
    else if (!cJSON_IsObject(root) || !cJSON_IsString(fmt) || strcmp(fmt->valuestring, dm_format_name(DM_FORMAT_PACK)) != 0)
        r = dm_fail(err, DM_ERR_FORMAT, "%s: not a JSON object with \"format\": \"dermis-pack\" (corrupt: "
                    "dermis-check FILE says more)", where);
    else
        r = json_version(cJSON_GetObjectItemCaseSensitive(root, "version"), where, &out->version, err);
    cJSON_Delete(root);
    free(text);
    return r;
}

/* A JSON object with "format": "dermis-scene", or without "format" but with a "mesh", as the
 * scene reader and dermis-check take it; "version" absent means 1. */
static dm_result scene_version(FILE *f, const char *path, dm_format_version *out, dm_error *err)
{
    long end = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (end < 0) return dm_fail(err, DM_ERR_FILE_READ, "%s: %s", path, strerror(errno));
    if (end > DM_FORMAT_SCENE_SIZE_MAX)
        return dm_fail(err, DM_ERR_FORMAT,
                       "%s: not a dermis pack (magic 89 44 50 4b 0d 0a 1a 0a) and %ld bytes, over the %d a scene "
                       "may have: expected a pack or a scene",
                       path, end, DM_FORMAT_SCENE_SIZE_MAX);
    char *text;
    size_t n;
    dm_result r = read_part(f, path, 0, (size_t)end, &text, &n, err);
    if (r != DM_OK) return r;
    cJSON *root = strlen(text) == n ? cJSON_ParseWithLength(text, n) : NULL;
    const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(root, "format");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "version");
    bool named = cJSON_IsString(fmt);
    if (!cJSON_IsObject(root)) {
        r = dm_fail(err, DM_ERR_FORMAT, "%s: neither a dermis pack (magic 89 44 50 4b 0d 0a 1a 0a) nor a JSON "
                    "object, expected a pack or a scene", path);
    } else if (fmt && (!named || strcmp(fmt->valuestring, dm_format_name(DM_FORMAT_SCENE)) != 0)) {
        r = dm_fail(err, DM_ERR_FORMAT, "%s: \"format\" %s%s%s, expected a pack or a scene (\"dermis-scene\")", path,
                    named ? "\"" : "", named ? fmt->valuestring : "not a string", named ? "\"" : "");
    } else if (!fmt && !cJSON_GetObjectItemCaseSensitive(root, "mesh")) {
        r = dm_fail(err, DM_ERR_FORMAT, "%s: a JSON object with neither \"format\" nor \"mesh\", expected a pack "
                    "or a scene", path);
    } else if (v) {
        out->stated = true;
        r = json_version(v, path, &out->version, err);
    } else {
        out->version = DM_SCENE_VERSION; /* dm_scene.h: "version" is optional */
    }
    cJSON_Delete(root);
    free(text);
    return r;
}

dm_result dm_format_version_read(const char *path, dm_format_version *out, dm_error *err)
{
    memset(out, 0, sizeof *out);
    int fd;
    dm_result r = dm_input_open(path, DM_INPUT_ANY, &fd, NULL, err);
    if (r != DM_OK) return r;
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        close(fd);
        return dm_fail(err, DM_ERR_FILE_OPEN, "%s: %s", path, strerror(errno));
    }
    uint8_t head[DM_PACK_HEADER_SIZE];
    size_t got = fread(head, 1, sizeof head, f);
    if (ferror(f)) {
        r = dm_fail(err, DM_ERR_FILE_READ, "%s: %s", path, strerror(errno));
    } else if (got >= 8 && memcmp(head, DM_PACK_MAGIC, 8) == 0) {
        out->kind = DM_FORMAT_PACK;
        out->stated = true;
        out->reads = DM_PACK_VERSION;
        r = pack_version(f, path, head, got, out, err);
    } else {
        out->kind = DM_FORMAT_SCENE;
        out->reads = DM_SCENE_VERSION;
        r = scene_version(f, path, out, err);
    }
    fclose(f);
    if (r != DM_OK) return r;
    out->verdict = dm_format_judge(out->version, out->reads);
    snprintf(out->summary, sizeof out->summary,
             "%s version %" PRId64 "%s (this dermis reads version %" PRId64 ": %s%s)", dm_format_name(out->kind), out->version,
             out->stated ? "" : ", not stated", out->reads,
             out->verdict == DM_FORMAT_READABLE ? "ok" : "refused, ", dm_format_advice(out->kind, out->verdict));
    return DM_OK;
}
