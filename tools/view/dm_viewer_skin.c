/* dm_viewer_skin.c — the live physical skin sliders (dm_viewer_skin.h). */
#include "dm_viewer_skin.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake/dm_skin_spec.h"
#include "core/dm_prov.h"

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

/* The skin the pack's profile was fitted to (the profile entry's provenance), if any. */
static bool pack_skin(const dm_viewer *v, dm_skin_params *p)
{
    const dm_pack_entry *e = v->pack_open ? dm_pack_find(&v->pack, "profile") : NULL;
    dm_provenance prov;
    dm_error ignored;
    if (!e || !e->provenance_json || dm_prov_from_json(&prov, e->provenance_json, v->pack.what, &ignored) != DM_OK)
        return false;
    const dm_param *spec = dm_prov_find(&prov, "skin");
    return spec && spec->type == DM_PARAM_STRING && dm_skin_spec_parse(spec->s, "pack skin", p, &ignored) == DM_OK;
}

void dm_viewer_skin_init(dm_viewer *v)
{
    dm_viewer_skin *k = &v->skin;
    memset(k, 0, sizeof *k);
    k->from_pack = pack_skin(v, &k->start);
    if (!k->from_pack) k->start = dm_skin_params_default();
    k->now = k->start;
    k->scale_rgb[0] = k->scale_rgb[1] = k->scale_rgb[2] = 1.0;
    dm_error err = {0};
    dm_profile w;
    if (dm_skin_weights_plan_init(&k->plan, v->profile.variance_mm2, v->profile.count, NULL, &err) != DM_OK ||
        dm_skin_weights_fit_colour(&k->plan, &k->start, NULL, &w, k->start_total, &err) != DM_OK) {
        snprintf(k->off_reason, sizeof k->off_reason, "%.255s", err.detail);
        dm_viewer_set_status(v, false, "skin sliders off: %s", err.detail);
        return;
    }
    k->available = true;
}

/* The sliders and scripts carry floats: a range's end as a float (0.1f is above 0.1) is that
 * end, not a value out of range. */
static double snap(double v, double lo, double hi)
{
    return v > hi && (float)v == (float)hi ? hi : v < lo && (float)v == (float)lo ? lo : v;
}

bool dm_viewer_skin_set(dm_viewer *v, const char *name, double value)
{
    dm_viewer_skin *k = &v->skin;
    if (!k->available) return dm_viewer_set_status(v, true, "%s: the skin sliders are off: %s", name, k->off_reason), false;
    dm_skin_params p = k->now;
    if (!strcmp(name, "melanin")) p.melanin_fraction = snap(value, 0.0, DM_SKIN_MELANIN_MAX);
    else if (!strcmp(name, "blood")) p.blood_fraction = snap(value, 0.0, DM_SKIN_BLOOD_MAX);
    else if (!strcmp(name, "epidermis")) p.epidermis_mm = snap(value, DM_SKIN_EPIDERMIS_MIN_MM, DM_SKIN_EPIDERMIS_MAX_MM);
    else return dm_viewer_set_status(v, true, "'%s' is not a skin slider (melanin, blood, epidermis)", name), false;
    double t0 = now_ms();
    dm_error err = {0};
    dm_profile w;
    double total[3], scale[3];
    if (dm_skin_weights_fit_colour(&k->plan, &p, v->profile.name, &w, total, &err) != DM_OK)
        return dm_viewer_set_status(v, true, "%s %g: %s", name, value, err.detail), false;
    /* the colour follows the skin's exact totals, not the weights' sums (dm_skin_weights.h) */
    for (int c = 0; c < 3; ++c) /* a channel the starting skin did not reflect stays as it is */
        scale[c] = k->start_total[c] > 0.0 ? total[c] / k->start_total[c] : 1.0;
    if (dm_renderer_set_profile_weights(v->r, &w, scale, &err) != DM_OK)
        return dm_viewer_set_status(v, true, "%s %g refused: %s", name, value, err.detail), false;
    k->ms[k->ms_count++ % DM_VIEWER_SKIN_TIMES] = now_ms() - t0;
    k->now = p;
    k->changed = true;
    memcpy(k->scale_rgb, scale, sizeof scale);
    memcpy(v->profile.weight, w.weight, sizeof w.weight); /* a rebuild keeps the skin */
    v->dirty = true;
    return true;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double dm_viewer_skin_median_ms(const dm_viewer *v)
{
    int n = v->skin.ms_count < DM_VIEWER_SKIN_TIMES ? v->skin.ms_count : DM_VIEWER_SKIN_TIMES;
    if (n == 0) return 0.0;
    double t[DM_VIEWER_SKIN_TIMES];
    memcpy(t, v->skin.ms, sizeof(double) * (size_t)n);
    qsort(t, (size_t)n, sizeof *t, cmp_double);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}
