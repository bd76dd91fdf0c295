#include "image/dm_exr.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "core/dm_file.h"
#include "core/dm_input.h"
#include "core/dm_parallel.h"

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

/* Parallel chunk encoding: each worker packs and compresses its chunks into memory; the
 * library's yield (write-order validation) and write steps are replaced, and the chunks
 * are written in order afterwards. */
typedef struct chunk_out {
    void *data;
    uint64_t size;
    exr_result_t rv;
} chunk_out;

typedef struct encode_job {
    exr_context_t f;
    int part, width, height, lines_per_chunk;
    const dm_exr_channel *channels;
    int channel_count;
    exr_chunk_info_t *infos;
    chunk_out *outs;
} encode_job;

static exr_result_t no_yield(exr_encode_pipeline_t *enc)
{
    (void)enc;
    return EXR_ERR_SUCCESS;
}

static exr_result_t capture_chunk(exr_encode_pipeline_t *enc)
{
    chunk_out *o = enc->encoding_user_data;
    if (!enc->compressed_buffer || enc->compressed_bytes == 0) return EXR_ERR_INVALID_ARGUMENT;
    o->data = malloc(enc->compressed_bytes);
    if (!o->data) return EXR_ERR_OUT_OF_MEMORY;
    memcpy(o->data, enc->compressed_buffer, enc->compressed_bytes);
    o->size = enc->compressed_bytes;
    return EXR_ERR_SUCCESS;
}

static void encode_chunks(void *ctx, size_t begin, size_t end)
{
    encode_job *j = ctx;
    const int w = j->width, lpc = j->lines_per_chunk;
    float *scratch = malloc(sizeof(float) * (size_t)w * (size_t)lpc * (size_t)j->channel_count);
    exr_encode_pipeline_t enc;
    int live = 0;
    for (size_t c = begin; c < end; ++c) {
        const exr_chunk_info_t *ci = &j->infos[c];
        chunk_out *o = &j->outs[c];
        if (!scratch) {
            o->rv = EXR_ERR_OUT_OF_MEMORY;
            continue;
        }
        /* this chunk's file lines (top-down) from bottom-up memory rows */
        for (int k = 0; k < j->channel_count; ++k)
            for (int l = 0; l < ci->height; ++l) {
                int row = j->height - 1 - (ci->start_y + l);
                memcpy(scratch + ((size_t)k * lpc + l) * w, j->channels[k].data + (size_t)row * w, sizeof(float) * w);
            }
        exr_result_t rv = live ? exr_encoding_update(j->f, j->part, ci, &enc)
                               : exr_encoding_initialize(j->f, j->part, ci, &enc);
        if (rv == EXR_ERR_SUCCESS) {
            live = 1;
            /* channels in the pipeline are in the file's sorted order: match by name */
            for (int k = 0; k < enc.channel_count; ++k) {
                int ch = 0;
                while (ch < j->channel_count && strcmp(j->channels[ch].name, enc.channels[k].channel_name) != 0) ++ch;
                assert(ch < j->channel_count);
                enc.channels[k].encode_from_ptr = (const uint8_t *)(scratch + (size_t)ch * lpc * w);
                enc.channels[k].user_pixel_stride = sizeof(float);
                enc.channels[k].user_line_stride = (int32_t)(sizeof(float) * w);
                enc.channels[k].user_data_type = EXR_PIXEL_FLOAT;
                enc.channels[k].user_bytes_per_element = sizeof(float);
            }
            rv = exr_encoding_choose_default_routines(j->f, j->part, &enc);
        }
        if (rv == EXR_ERR_SUCCESS) {
            enc.yield_until_ready_fn = no_yield;
            enc.write_fn = capture_chunk;
            enc.encoding_user_data = o;
            rv = exr_encoding_run(j->f, j->part, &enc);
        }
        o->rv = rv;
    }
    if (live) exr_encoding_destroy(j->f, &enc);
    free(scratch);
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
    int chunk_count = lines_per_chunk > 0 ? (height + lines_per_chunk - 1) / lines_per_chunk : 0;
    encode_job job = {.f = f, .part = part, .width = width, .height = height, .lines_per_chunk = lines_per_chunk,
                      .channels = channels, .channel_count = channel_count};
    if (rv == EXR_ERR_SUCCESS) {
        stage = "pixels";
        job.infos = calloc((size_t)chunk_count, sizeof *job.infos);
        job.outs = calloc((size_t)chunk_count, sizeof *job.outs);
        if (!job.infos || !job.outs) rv = EXR_ERR_OUT_OF_MEMORY;
    }
    /* Chunk layout in file order, then compression on every core (each chunk is
     * independent), then the chunks written in order: the same bytes as one thread. */
    for (int c = 0; c < chunk_count && rv == EXR_ERR_SUCCESS; ++c)
        rv = exr_write_scanline_chunk_info(f, part, c * lines_per_chunk, &job.infos[c]);
    if (rv == EXR_ERR_SUCCESS) dm_parallel_for((size_t)chunk_count, 1, 0, encode_chunks, &job);
    for (int c = 0; c < chunk_count && rv == EXR_ERR_SUCCESS; ++c) {
        rv = job.outs[c].rv;
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_write_scanline_chunk(f, part, job.infos[c].start_y, job.outs[c].data, job.outs[c].size);
    }
    for (int c = 0; job.outs && c < chunk_count; ++c) free(job.outs[c].data);
    free(job.outs);
    free(job.infos);
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
    dm_result ir = dm_input_check(path, DM_INPUT_IMAGE, NULL, err); /* OpenEXR opens it by name */
    if (ir != DM_OK) return ir;
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
        if (w <= 0 || h <= 0 || w > DM_EXR_SIDE_MAX || h > DM_EXR_SIDE_MAX || chl->num_channels <= 0 ||
            w * h * chl->num_channels > DM_EXR_FLOATS_MAX) {
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
