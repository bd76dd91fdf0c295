#include "bake/dm_exr.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "core/dm_file.h"

/* Errors from the library land here instead of on stderr (TOOLCHAIN.md). */
typedef struct exr_msg {
    char text[512];
} exr_msg;

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS && ud) {
        exr_msg *m = ud;
        snprintf(m->text, sizeof m->text, "%s (%s)", msg ? msg : "", exr_get_error_code_as_string(code));
    }
}

static dm_result exr_fail(dm_error *err, dm_result code, const char *path, const char *what, exr_result_t rv,
                          const exr_msg *m)
{
    return dm_fail(err, code, "%s: %s: %s", path, what,
                   m && m->text[0] ? m->text : exr_get_default_error_message(rv));
}

static void set_typed_attributes(exr_context_t f, const dm_provenance *prov)
{
    char name[64];
    exr_attr_set_string(f, 0, "dm.tool", prov->tool);
    exr_attr_set_string(f, 0, "dm.version", prov->version);
    if (prov->input_hash[0]) exr_attr_set_string(f, 0, "dm.input_hash", prov->input_hash);
    for (int k = 0; k < prov->param_count; ++k) {
        const dm_param *q = &prov->params[k];
        if (snprintf(name, sizeof name, "dm.%s", q->name) > 31) continue; /* JSON keeps it */
        if (q->type == DM_PARAM_INT && q->i >= INT32_MIN && q->i <= INT32_MAX)
            exr_attr_set_int(f, 0, name, (int32_t)q->i);
        else if (q->type == DM_PARAM_STRING)
            exr_attr_set_string(f, 0, name, q->s);
        else
            exr_attr_set_double(f, 0, name, q->d);
    }
}

dm_result dm_exr_write(const char *path, int width, int height, const dm_exr_channel *channels, int channel_count,
                       const dm_provenance *prov, dm_error *err)
{
    assert(path && channels && channel_count > 0 && prov);
    if (width <= 0 || height <= 0)
        return dm_fail(err, DM_ERR_INVALID_ARGUMENT, "%s: image size %dx%d is empty", path, width, height);
    char json[16384];
    dm_result r = dm_prov_to_json(prov, json, sizeof json, err);
    if (r != DM_OK) return r;
    dm_atomic_file af;
    if ((r = dm_atomic_begin(&af, path, err)) != DM_OK) return r;

    exr_msg msg = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &msg;
    exr_context_t f = NULL;
    exr_result_t rv = exr_start_write(&f, af.tmp_path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        dm_atomic_abort(&af);
        return exr_fail(err, DM_ERR_FILE_WRITE, path, "cannot create", rv, &msg);
    }
    int part = 0;
    float *scratch = NULL;
    exr_encode_pipeline_t enc;
    int enc_live = 0;
    const char *stage = "header";
    rv = exr_add_part(f, "dermis", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS) rv = exr_initialize_required_attr_simple(f, part, width, height, EXR_COMPRESSION_ZIP);
    for (int c = 0; c < channel_count && rv == EXR_ERR_SUCCESS; ++c)
        rv = exr_add_channel(f, part, channels[c].name,
                             channels[c].type == DM_EXR_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS) {
        exr_attr_set_string(f, part, "dermis.provenance", json);
        set_typed_attributes(f, prov);
        rv = exr_write_header(f);
    }
    int32_t lines_per_chunk = 1;
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(f, part, &lines_per_chunk);
    if (rv == EXR_ERR_SUCCESS) {
        stage = "pixels";
        scratch = malloc(sizeof(float) * (size_t)width * (size_t)lines_per_chunk * (size_t)channel_count);
        if (!scratch) rv = EXR_ERR_OUT_OF_MEMORY;
    }
    for (int y = 0; y < height && rv == EXR_ERR_SUCCESS; y += lines_per_chunk) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(f, part, y, &ci);
        if (rv != EXR_ERR_SUCCESS) break;
        /* Gather this chunk's file lines (top-down) from bottom-up memory rows. */
        for (int c = 0; c < channel_count; ++c)
            for (int l = 0; l < ci.height; ++l) {
                int row = height - 1 - (ci.start_y + l);
                memcpy(scratch + ((size_t)c * lines_per_chunk + l) * width,
                       channels[c].data + (size_t)row * width, sizeof(float) * width);
            }
        rv = enc_live ? exr_encoding_update(f, part, &ci, &enc) : exr_encoding_initialize(f, part, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS) break;
        enc_live = 1;
        /* Channels in the pipeline are in the file's sorted order: match by name. */
        for (int k = 0; k < enc.channel_count; ++k) {
            int c = 0;
            while (c < channel_count && strcmp(channels[c].name, enc.channels[k].channel_name) != 0) ++c;
            assert(c < channel_count);
            enc.channels[k].encode_from_ptr = (const uint8_t *)(scratch + (size_t)c * lines_per_chunk * width);
            enc.channels[k].user_pixel_stride = sizeof(float);
            enc.channels[k].user_line_stride = (int32_t)(sizeof(float) * width);
            enc.channels[k].user_data_type = EXR_PIXEL_FLOAT;
            enc.channels[k].user_bytes_per_element = sizeof(float);
        }
        rv = exr_encoding_choose_default_routines(f, part, &enc);
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(f, part, &enc);
    }
    if (enc_live) exr_encoding_destroy(f, &enc);
    free(scratch);
    exr_result_t frv = exr_finish(&f);
    if (rv == EXR_ERR_SUCCESS) rv = frv;
    if (rv != EXR_ERR_SUCCESS) {
        dm_atomic_abort(&af);
        return exr_fail(err, DM_ERR_FILE_WRITE, path, stage, rv, &msg);
    }
    return dm_atomic_commit(&af, err);
}

void dm_exr_free(dm_exr_image *img)
{
    if (!img) return;
    if (img->planes)
        for (int c = 0; c < img->channel_count; ++c) free(img->planes[c]);
    free(img->planes);
    free(img->names);
    memset(img, 0, sizeof *img);
}

const float *dm_exr_find(const dm_exr_image *img, const char *name)
{
    for (int c = 0; c < img->channel_count; ++c)
        if (strcmp(img->names[c], name) == 0) return img->planes[c];
    return NULL;
}

static dm_result read_chunks(exr_context_t f, const char *path, dm_exr_image *out, int tiled, exr_msg *msg,
                             dm_error *err)
{
    exr_attr_box2i_t dw;
    exr_result_t rv = exr_get_data_window(f, 0, &dw);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, DM_ERR_FORMAT, path, "data window", rv, msg);
    int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    /* Scanline files: one chunk per lines_per_chunk lines. Tiled files: level (0, 0)
     * only, tiles in row-major order. */
    int32_t lines_per_chunk = 1, tw = 0, th = 0;
    int32_t ntx = 1, nchunks;
    if (tiled) {
        if (exr_get_tile_sizes(f, 0, 0, 0, &tw, &th) != EXR_ERR_SUCCESS || tw <= 0 || th <= 0)
            return dm_fail(err, DM_ERR_FORMAT, "%s: bad tile description", path);
        ntx = (w + tw - 1) / tw;
        nchunks = ntx * ((h + th - 1) / th);
    } else {
        if (exr_get_scanlines_per_chunk(f, 0, &lines_per_chunk) != EXR_ERR_SUCCESS || lines_per_chunk <= 0)
            return dm_fail(err, DM_ERR_FORMAT, "%s: bad scanlines per chunk", path);
        nchunks = (h + lines_per_chunk - 1) / lines_per_chunk;
    }
    exr_decode_pipeline_t dec;
    int dec_live = 0;
    for (int32_t idx = 0; idx < nchunks; ++idx) {
        exr_chunk_info_t ci;
        if (tiled)
            rv = exr_read_tile_chunk_info(f, 0, idx % ntx, idx / ntx, 0, 0, &ci);
        else
            rv = exr_read_scanline_chunk_info(f, 0, dw.min.y + idx * lines_per_chunk, &ci);
        if (rv != EXR_ERR_SUCCESS) {
            if (dec_live) exr_decoding_destroy(f, &dec);
            return exr_fail(err, DM_ERR_FORMAT, path, "chunk table", rv, msg);
        }
        rv = dec_live ? exr_decoding_update(f, 0, &ci, &dec) : exr_decoding_initialize(f, 0, &ci, &dec);
        if (rv != EXR_ERR_SUCCESS) {
            if (dec_live) exr_decoding_destroy(f, &dec);
            return exr_fail(err, DM_ERR_FORMAT, path, "decoder", rv, msg);
        }
        dec_live = 1;
        int x0 = ci.start_x - dw.min.x, y0 = ci.start_y - dw.min.y;
        for (int k = 0; k < dec.channel_count; ++k) {
            int c = 0;
            while (c < out->channel_count && strcmp(out->names[c], dec.channels[k].channel_name) != 0) ++c;
            if (c == out->channel_count || dec.channels[k].x_samples != 1 || dec.channels[k].y_samples != 1) {
                dec.channels[k].decode_to_ptr = NULL; /* subsampled channels are skipped */
                continue;
            }
            /* File line y0 (top-down) goes to memory row h-1-y0; walk upward in memory. */
            float *dst = out->planes[c] + (size_t)(h - 1 - y0) * w + x0;
            dec.channels[k].decode_to_ptr = (uint8_t *)dst;
            dec.channels[k].user_pixel_stride = sizeof(float);
            dec.channels[k].user_line_stride = -(int32_t)(sizeof(float) * w);
            dec.channels[k].user_data_type = EXR_PIXEL_FLOAT;
            dec.channels[k].user_bytes_per_element = sizeof(float);
        }
        rv = exr_decoding_choose_default_routines(f, 0, &dec);
        if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(f, 0, &dec);
        if (rv != EXR_ERR_SUCCESS) {
            exr_decoding_destroy(f, &dec);
            return exr_fail(err, DM_ERR_FORMAT, path, "pixel data", rv, msg);
        }
    }
    if (dec_live) exr_decoding_destroy(f, &dec);
    return DM_OK;
}

dm_result dm_exr_read(const char *path, dm_exr_image *out, dm_error *err)
{
    assert(path && out);
    memset(out, 0, sizeof *out);
    exr_msg msg = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &msg;
    exr_context_t f = NULL;
    exr_result_t rv = exr_start_read(&f, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&f);
        return exr_fail(err, rv == EXR_ERR_FILE_ACCESS ? DM_ERR_FILE_OPEN : DM_ERR_FORMAT, path,
                        "not a readable OpenEXR file", rv, &msg);
    }
    dm_result r = DM_OK;
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl = NULL;
    if (exr_get_storage(f, 0, &storage) != EXR_ERR_SUCCESS || exr_get_data_window(f, 0, &dw) != EXR_ERR_SUCCESS ||
        exr_get_channels(f, 0, &chl) != EXR_ERR_SUCCESS || !chl) {
        r = dm_fail(err, DM_ERR_FORMAT, "%s: missing storage, data window or channel list", path);
    } else if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
        r = dm_fail(err, DM_ERR_UNSUPPORTED, "%s: deep EXR parts are not supported", path);
    } else {
        int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
        if (w <= 0 || h <= 0 || w * h > ((int64_t)1 << 28) || chl->num_channels <= 0) {
            r = dm_fail(err, DM_ERR_FORMAT, "%s: image of %lldx%lld with %d channels is out of range", path,
                        (long long)w, (long long)h, chl->num_channels);
        } else {
            out->width = (int)w;
            out->height = (int)h;
            out->channel_count = chl->num_channels;
            out->names = calloc((size_t)chl->num_channels, sizeof *out->names);
            out->planes = calloc((size_t)chl->num_channels, sizeof *out->planes);
            if (!out->names || !out->planes) r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
            for (int c = 0; c < chl->num_channels && r == DM_OK; ++c) {
                snprintf(out->names[c], DM_EXR_NAME_SIZE, "%s", chl->entries[c].name.str);
                out->planes[c] = calloc((size_t)(w * h), sizeof(float));
                if (!out->planes[c])
                    r = dm_fail(err, DM_ERR_OUT_OF_MEMORY, "%s: out of memory for %lldx%lld", path, (long long)w,
                                (long long)h);
            }
            if (r == DM_OK) r = read_chunks(f, path, out, storage == EXR_STORAGE_TILED, &msg, err);
        }
    }
    if (r == DM_OK) {
        const exr_attribute_t *a = NULL;
        if (exr_get_attribute_by_name(f, 0, "dermis.provenance", &a) == EXR_ERR_SUCCESS && a &&
            a->type == EXR_ATTR_STRING && a->string && a->string->str) {
            char *json = malloc((size_t)a->string->length + 1);
            if (json) {
                memcpy(json, a->string->str, (size_t)a->string->length);
                json[a->string->length] = '\0';
                out->has_provenance = dm_prov_from_json(&out->prov, json, path, NULL) == DM_OK;
                free(json);
            }
        }
    }
    exr_finish(&f);
    if (r != DM_OK) dm_exr_free(out);
    return r;
}
