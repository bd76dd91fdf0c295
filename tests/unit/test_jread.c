/* The strict JSON reader shared by the scene and the pack manifest (core/dm_jread.h): each
 * refusal names the place, the JSON path, the value and what was expected. */
#include <criterion/criterion.h>
#include <string.h>

#include "core/dm_jread.h"
#include "core/dm_prov.h"

static cJSON *doc(const char *text)
{
    cJSON *j = cJSON_Parse(text);
    cr_assert(j, "test JSON does not parse: %s", text);
    return j;
}

#define EXPECT_DETAIL(err, s) cr_expect(strstr((err).detail, s) != NULL, "\"%s\" not in: %s", s, (err).detail)

Test(jread, keys_unknown_and_twice)
{
    static const char *const keys[] = {"a", "b", NULL};
    dm_error err = {0};
    dm_jread c = {"f.json", &err, DM_OK};
    cJSON *j = doc("{\"a\": 1, \"c\": 2}");
    cr_expect_not(dm_jread_keys(&c, j, "$", keys));
    cr_expect_eq(c.r, DM_ERR_FORMAT);
    EXPECT_DETAIL(err, "f.json: $.c: unknown key, expected one of: a, b");
    cJSON_Delete(j);
    j = doc("{\"a\": 1, \"a\": 2}");
    cr_expect_not(dm_jread_keys(&c, j, "$", keys));
    EXPECT_DETAIL(err, "$.a: key given twice");
    cJSON_Delete(j);
}

Test(jread, numbers_ranges_and_types)
{
    dm_error err = {0};
    dm_jread c = {"f.json", &err, DM_OK};
    cJSON *j = doc("{\"n\": 4, \"x\": 1.5, \"s\": \"t\", \"big\": 1e300}");
    int n = 0;
    cr_expect(dm_jread_int_opt(&c, j, "$", "n", 0, 10, false, &n) && n == 4);
    cr_expect_not(dm_jread_int_opt(&c, j, "$", "n", 0, 10, true, &n));
    EXPECT_DETAIL(err, "$.n: 4 is not an odd integer in [0, 10]");
    cr_expect_not(dm_jread_int_opt(&c, j, "$", "x", 0, 10, false, &n));
    cr_expect_eq(c.r, DM_ERR_RANGE);
    cr_expect_not(dm_jread_int_opt(&c, j, "$", "s", 0, 10, false, &n));
    cr_expect_eq(c.r, DM_ERR_FORMAT);
    double d = 7;
    cr_expect(dm_jread_double_opt(&c, j, "$", "absent", 0, 1, &d) && d == 7, "an absent optional keeps *out");
    cr_expect_not(dm_jread_double_opt(&c, j, "$", "big", 0, 1e6, &d));
    int64_t v = 0;
    cr_expect_not(dm_jread_int64(&c, j, "$", "absent", 0, 9, &v));
    EXPECT_DETAIL(err, "$.absent: missing, expected an integer in [0, 9]");
    cr_expect_eq(dm_jread_string(&c, j, "$", "s")[0], 't');
    cr_expect_null(dm_jread_string(&c, j, "$", "n"));
    EXPECT_DETAIL(err, "$.n: 4 is not a string");
    cJSON_Delete(j);
}

Test(jread, vec3_and_objects)
{
    dm_error err = {0};
    dm_jread c = {"x.dpk: manifest", &err, DM_OK};
    cJSON *j = doc("{\"v\": [0, 0, 0], \"w\": [1, 2], \"o\": 3}");
    float out[3] = {9, 9, 9};
    cr_expect_not(dm_jread_vec3_opt(&c, j, "$", "v", -1, 1, true, out));
    EXPECT_DETAIL(err, "x.dpk: manifest: $.v: [0,0,0] is not an array of 3 numbers in [-1, 1], not all zero");
    cr_expect(out[0] == 9, "a refused value leaves *out alone");
    cr_expect(dm_jread_vec3_opt(&c, j, "$", "v", -1, 1, false, out) && out[0] == 0);
    cr_expect_not(dm_jread_vec3_opt(&c, j, "$", "w", -1, 1, false, out));
    bool ok = true;
    cr_expect_null(dm_jread_object(&c, j, "$", "o", false, &ok));
    cr_expect_not(ok);
    cr_expect_null(dm_jread_object(&c, j, "$", "none", false, &ok));
    cr_expect(ok, "an absent optional object is not an error");
    cr_expect_null(dm_jread_object(&c, j, "$", "none", true, &ok));
    cr_expect_not(ok);
    EXPECT_DETAIL(err, "$.none: missing, expected an object");
    cJSON_Delete(j);
}

/* Provenance JSON (core/dm_prov.h) is read by the same reader: a known parameter round-trips,
 * a stray key, a bad name or an array value is refused with its JSON path. */
Test(jread, provenance_is_read_strictly)
{
    dm_provenance p;
    dm_error err = {0};
    cr_expect_eq(dm_prov_from_json(&p, "{\"tool\":\"t\",\"version\":\"1\",\"input_hash\":\"h\",\"params\":{\"n\":3,\"x\":0.5,"
                                       "\"s\":\"v\",\"z\":null}}", "a.png", &err), DM_OK, "%s", err.detail);
    cr_expect_eq(p.param_count, 4);
    cr_expect_str_eq(p.tool, "t");
    cr_expect_eq(dm_prov_from_json(&p, "{\"tool\":\"t\",\"version\":\"1\",\"params\":{},\"extra\":1}", "b.png", &err),
                 DM_ERR_FORMAT);
    EXPECT_DETAIL(err, "b.png: provenance: $.extra: unknown key");
    cr_expect_eq(dm_prov_from_json(&p, "{\"tool\":\"t\",\"version\":\"1\",\"params\":{\"Bad Name\":1}}", "c.png", &err),
                 DM_ERR_FORMAT);
    EXPECT_DETAIL(err, "$.params.Bad Name");
    cr_expect_eq(dm_prov_from_json(&p, "{\"tool\":\"t\",\"version\":\"1\",\"params\":{\"a\":[1]}}", "d.png", &err),
                 DM_ERR_FORMAT);
    EXPECT_DETAIL(err, "$.params.a: [1] is not a string, a number or null");
    cr_expect_eq(dm_prov_from_json(&p, "{\"version\":\"1\",\"params\":{}}", "e.png", &err), DM_ERR_FORMAT);
    EXPECT_DETAIL(err, "$.tool: missing, expected a string");
    cr_expect_eq(p.param_count, 0, "a refused provenance is left empty");
}
