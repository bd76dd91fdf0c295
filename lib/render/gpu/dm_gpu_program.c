/* dm_gpu_program.c — programs from source (dm_gpu_program.h). */
#include "render/gpu/dm_gpu_program.h"

/* Whether a compile (shader) or a link (program) failed; then its log, NUL-terminated. */
static bool failed(GLuint obj, bool program, char *log, GLsizei log_size)
{
    GLint ok = 0;
    if (program) glGetProgramiv(obj, GL_LINK_STATUS, &ok);
    else glGetShaderiv(obj, GL_COMPILE_STATUS, &ok);
    if (ok) return false;
    log[0] = '\0';
    if (program) glGetProgramInfoLog(obj, log_size, NULL, log);
    else glGetShaderInfoLog(obj, log_size, NULL, log);
    return true;
}

static dm_result compile_stage(dmg *g, GLenum stage, const char *defines, const char *common, const char *src,
                               const char *name, GLuint *out, dm_error *err)
{
    const char *stage_define = stage == GL_VERTEX_SHADER ? "#define DM_VERTEX 1\n" : "#define DM_FRAGMENT 1\n";
    dmg_kind kind = stage == GL_VERTEX_SHADER ? DMG_VERTEX_SHADER : DMG_FRAGMENT_SHADER;
    GLuint sh = dmg_make(g, kind);
    /* "#line 1" before the pass keeps compiler messages in the pass file's numbering */
    const char *with_line[7] = {"#version 330 core\n", stage_define, defines, "#line 1 1\n", common,
                                "\n#line 1 2\n", src};
    glShaderSource(sh, 7, with_line, NULL);
    glCompileShader(sh);
    char log[768];
    if (failed(sh, false, log, sizeof log)) {
        dmg_free(g, kind, sh);
        return dm_fail(err, DM_ERR_GL, "%s (%s stage; source 1 = common.glsl, 2 = the pass): %s", name,
                       stage == GL_VERTEX_SHADER ? "vertex" : "fragment", log);
    }
    *out = sh;
    return DM_OK;
}

dm_result dmg_program(dmg *g, const char *name, const char *defines, const char *common, const char *src,
                      const char *const *attribs, int attrib_count, GLuint *out, dm_error *err)
{
    GLuint vs = 0, fs = 0;
    dm_result rc = compile_stage(g, GL_VERTEX_SHADER, defines, common, src, name, &vs, err);
    if (rc == DM_OK) rc = compile_stage(g, GL_FRAGMENT_SHADER, defines, common, src, name, &fs, err);
    if (rc != DM_OK) {
        dmg_free(g, DMG_VERTEX_SHADER, vs);
        return rc;
    }
    GLuint prog = dmg_make(g, DMG_PROGRAM);
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    for (int i = 0; i < attrib_count; ++i) glBindAttribLocation(prog, (GLuint)i, attribs[i]);
    glLinkProgram(prog);
    dmg_free(g, DMG_VERTEX_SHADER, vs);
    dmg_free(g, DMG_FRAGMENT_SHADER, fs);
    char log[768];
    if (failed(prog, true, log, sizeof log)) {
        dmg_free(g, DMG_PROGRAM, prog);
        return dm_fail(err, DM_ERR_GL, "%s: link failed: %s", name, log);
    }
    *out = prog;
    return DM_OK;
}
