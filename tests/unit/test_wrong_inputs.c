/* Never a silent wrong answer (issue 17 point 5): each wrong input gives a warning or an
 * error that names the fix. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../common/expect_tool.h"

#define HEAD DERMIS_ASSETS "/lps/LeePerrySmith.obj"
#define ENV DERMIS_ASSETS "/env/venice_sunset_1k.hdr"

static char dir[256];
static void setup(void) { cr_assert(test_tmpdir(dir, sizeof dir)); }
#define expect(cmd, rc, n1, n2) ((void)test_expect_tool(dir, 0, cmd, rc, n1, n2))

Test(wrong_inputs, ldr_environment_refused_with_the_conversion, .init = setup)
{
    expect("oiiotool " ENV " -d uint8 -o env.png && oiiotool " ENV " -d uint8 -o env.jpg", 0, NULL, NULL);
    expect(DERMIS_BIN "/dermis-bake-env env.png -o e.exr --samples 16", 2, "8-bit", "oiiotool env.png --colorconvert");
    expect(DERMIS_BIN "/dermis-bake-env env.jpg -o e.exr --samples 16", 2, "not radiance", ".hdr or .exr");
    cr_expect_eq(test_count_files(dir, "e.exr"), 0);
}

Test(wrong_inputs, stl_without_uvs_names_the_fix, .init = setup)
{
    FILE *f = NULL;
    char p[320];
    snprintf(p, sizeof p, "%s/t.stl", dir);
    cr_assert((f = fopen(p, "w")));
    fputs("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
          "endsolid t\n",
          f);
    fclose(f);
    expect(DERMIS_BIN "/dermis-bake-stretch t.stl -o s.exr --size 64", 2, "no texture coordinates",
           "export the mesh with its UVs");
}

Test(wrong_inputs, inward_winding_warned, .init = setup)
{
    /* the head with every face's corners reversed: same surface, normals inward */
    expect("awk '$1==\"f\"{l=\"f\"; for(i=NF;i>1;--i) l=l\" \"$i; print l > \"flipped.obj\"; next} "
           "{print > \"flipped.obj\"}' " HEAD, 0, NULL, NULL);
    expect(DERMIS_BIN "/dermis-bake-stretch flipped.obj -o s.exr --size 64 --quiet", 0, "faces wind inward",
           "flip the faces");
    /* the head as it is: no warning */
    char log[320];
    snprintf(log, sizeof log, "%s/log.txt", dir);
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " -o s.exr --size 64 --quiet", 0, NULL, NULL);
    char *text = test_slurp(log);
    cr_expect(text && !strstr(text, "wind inward") && !strstr(text, "mm_per_unit"), "%s", text ? text : "");
    free(text);
}

Test(wrong_inputs, implausible_mm_per_unit_warned, .init = setup)
{
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " -o s.exr --size 64 --mm-per-unit 1 --quiet", 0,
           "spans 8.553 mm", "set mm_per_unit to about");
    expect(DERMIS_BIN "/dermis-bake-stretch " HEAD " -o s.exr --size 64 --mm-per-unit 1000 --quiet", 0,
           "like hard plastic", "set mm_per_unit to about");
}

Test(wrong_inputs, rotated_env_bake_warns_that_packs_refuse_it, .init = setup)
{
    expect(DERMIS_BIN "/dermis-bake-env " ENV " -o e.exr --samples 16 --rotate 90 --quiet", 0,
           "dermis-pack takes only unrotated bakes", "rotation_deg 90");
}

Test(wrong_inputs, scene_without_light_or_environment_warned, .init = setup)
{
    char p[320];
    snprintf(p, sizeof p, "%s/dark.json", dir);
    FILE *f = fopen(p, "w");
    cr_assert(f);
    fputs("{\"mesh\": {\"path\": \"" HEAD "\"}, \"effects\": {\"specular\": true}}", f);
    fclose(f);
    expect(DERMIS_BIN "/dermis-pack dark.json --explain", 0, "no light and no environment", "add a light");
}

Test(wrong_inputs, scene_given_to_the_renderer_says_pack_it_first, .init = setup)
{
    expect(DERMIS_BIN "/dermis-render scene.json -o x.png", 2, "not a pack: pack it first",
           "dermis-pack scene.json -o scene.dpk");
}
