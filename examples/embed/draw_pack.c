/* draw_pack.c — a .dpk pack drawn by YOUR OWN OpenGL code, with dermis used only as a file
 * reader (lib/core: the pack reader, the scene, the PNG writer; not the renderer).
 *
 *   draw_pack PACK.dpk OUT.png [WIDTH HEIGHT]
 *
 * What it shows an engine programmer:
 *   - dm_pack_open maps the file and verifies every byte of it (checksums, schema, sizes,
 *     finite floats, indices in range) before you touch anything: after it succeeds the
 *     blobs can go straight to glBufferData / glTexImage2D, no parsing, no copies.
 *   - the vertex blob is interleaved float32 in one fixed layout (pack/dm_pack.h,
 *     DM_PACK_VERTEX_*): position, normal, uv, tangent; indices are uint32 triangles.
 *   - textures are stored bottom-up (row 0 is v = 0), so they upload as they are.
 *   - the pack carries its scene (camera, lights, output size) as a parsed struct.
 * The GL side is an ordinary GL 3.3 core program: an OSMesa context made here, an FBO,
 * one VAO, one shader (albedo x Lambert + ambient). No tone mapping, no subsurface: that is
 * what the dermis renderer is for (see render_into_fbo.c).
 * Exit codes: 0 done, 1 usage, 2 the pack cannot be read, 3 OpenGL failed, 4 the PNG
 * cannot be written.
 */
#define GL_GLEXT_PROTOTYPES 1 /* OSMesa exports every GL entry point: no loader needed */
#include <GL/osmesa.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "pack/dm_pack.h"
#include "core/dm_png.h"
#include "core/dm_scene.h"

static const char *vertex_src =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "uniform mat4 u_view_proj;\n"
    "out vec3 v_normal;\n"
    "out vec2 v_uv;\n"
    "void main() {\n"
    "    v_normal = a_normal;\n"
    "    v_uv = a_uv;\n"
    "    gl_Position = u_view_proj * vec4(a_position, 1.0);\n"
    "}\n";

/* The albedo texture is GL_SRGB8_ALPHA8, so texture() returns linear colour; the target is
 * sRGB too and GL_FRAMEBUFFER_SRGB encodes on write. */
static const char *fragment_src =
    "#version 330 core\n"
    "in vec3 v_normal;\n"
    "in vec2 v_uv;\n"
    "uniform sampler2D u_albedo;\n"
    "uniform vec3 u_to_light;\n"
    "uniform vec3 u_light_color;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 albedo = texture(u_albedo, v_uv).rgb;\n"
    "    float n_dot_l = max(dot(normalize(v_normal), u_to_light), 0.0);\n"
    "    o_color = vec4(albedo * (0.85 * u_light_color * n_dot_l + 0.12), 1.0);\n"
    "}\n";

/* ---- a few lines of matrix math (column-major, as GL takes it) ---- */

static void normalize3(float v[3])
{
    float n = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i) v[i] /= n;
}

static void cross3(float o[3], const float a[3], const float b[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* projection · view for a camera at eye looking at target (right-handed, GL clip space) */
static void view_proj(float m[16], const dm_scene *s, float aspect, float near, float far)
{
    float f[3], r[3], u[3];
    for (int i = 0; i < 3; ++i) f[i] = s->camera_target[i] - s->camera_eye[i];
    normalize3(f);
    cross3(r, f, s->camera_up);
    normalize3(r);
    cross3(u, r, f);
    float view[16] = {r[0], u[0], -f[0], 0, r[1], u[1], -f[1], 0, r[2], u[2], -f[2], 0, 0, 0, 0, 1};
    for (int i = 0; i < 3; ++i) {
        view[12] -= r[i] * s->camera_eye[i];
        view[13] -= u[i] * s->camera_eye[i];
        view[14] += f[i] * s->camera_eye[i];
    }
    float t = 1.0f / tanf(s->fov_y_deg * 3.14159265f / 360.0f);
    float proj[16] = {t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (far + near) / (near - far), -1,
                      0, 0, 2 * far * near / (near - far), 0};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            float sum = 0;
            for (int k = 0; k < 4; ++k) sum += proj[k * 4 + row] * view[c * 4 + k];
            m[c * 4 + row] = sum;
        }
}

static GLuint compile(GLenum stage, const char *src)
{
    GLuint sh = glCreateShader(stage);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        fprintf(stderr, "error: shader: %s\n", log);
    }
    return sh;
}

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 5) {
        fprintf(stderr, "Usage: draw_pack PACK.dpk OUT.png [WIDTH HEIGHT]  (default: the scene's size)\n");
        return 1;
    }

    /* 1. Open the pack: mapped read-only and verified whole; nothing is copied. */
    dm_error err = {0};
    dm_pack pack;
    dm_scene scene;
    const dm_pack_entry *vertices, *indices, *albedo;
    if (dm_pack_open(argv[1], &pack, &err) != DM_OK || dm_pack_scene(&pack, &scene, &err) != DM_OK ||
        dm_pack_mesh(&pack, &vertices, &indices, &err) != DM_OK ||
        dm_pack_find_texture(&pack, "albedo", &albedo, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        dm_pack_close(&pack);
        return 2;
    }
    if (albedo && albedo->format != DM_TEX_RGBA8_SRGB) albedo = NULL; /* the packer writes rgba8_srgb */
    int width = argc == 5 ? atoi(argv[3]) : scene.width, height = argc == 5 ? atoi(argv[4]) : scene.height;
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        fprintf(stderr, "error: size %dx%d, expected 1..16384 per side\n", width, height);
        dm_pack_close(&pack);
        return 1;
    }

    /* 2. A headless GL 3.3 core context. OSMesa insists on a client colour buffer even
     *    when everything renders into FBOs: a 1x1 one will do. */
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    static uint32_t client_pixel;
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx || !OSMesaMakeCurrent(ctx, &client_pixel, GL_UNSIGNED_BYTE, 1, 1)) {
        fprintf(stderr, "error: OSMesa: no 3.3 core context\n");
        if (ctx) OSMesaDestroyContext(ctx);
        dm_pack_close(&pack);
        return 3;
    }

    /* 3. Our render target: sRGB colour + depth. */
    GLuint fbo, rb[2];
    glGenRenderbuffers(2, rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_SRGB8_ALPHA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);

    /* 4. The mesh blobs go to GL as they are: 48-byte vertices, uint32 indices. */
    GLuint vao, buffers[2];
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, buffers);
    glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)vertices->size, vertices->data, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)indices->size, indices->data, GL_STATIC_DRAW);
    const int offsets[3] = {DM_PACK_VERTEX_POSITION, DM_PACK_VERTEX_NORMAL, DM_PACK_VERTEX_UV};
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, DM_PACK_VERTEX_STRIDE,
                              (const void *)(size_t)offsets[a]);
    }

    /* 5. The albedo map: rows bottom-up already, tightly packed (alignment 1). Without
     *    one, a 1x1 white texture. */
    static const uint8_t white[4] = {255, 255, 255, 255};
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, albedo ? albedo->width : 1, albedo ? albedo->height : 1, 0,
                 GL_RGBA, GL_UNSIGNED_BYTE, albedo ? albedo->data : white);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);

    /* 6. The shader, and its inputs from the scene: the camera as stored, near and far
     *    planes around the mesh's bounding sphere, the first directional light (else a
     *    light at the camera). Its intensity is for an HDR renderer: only its colour and
     *    direction are used here. */
    GLuint prog = glCreateProgram(), vs = compile(GL_VERTEX_SHADER, vertex_src),
           fs = compile(GL_FRAGMENT_SHADER, fragment_src);
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    glUseProgram(prog);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const float *v = vertices->data;
    for (int64_t i = 0; i < vertices->vertex_count; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fminf(lo[k], v[i * DM_PACK_VERTEX_STRIDE / 4 + k]);
            hi[k] = fmaxf(hi[k], v[i * DM_PACK_VERTEX_STRIDE / 4 + k]);
        }
    float d2 = 0, r2 = 0;
    for (int k = 0; k < 3; ++k) {
        float c = 0.5f * (lo[k] + hi[k]), e = c - scene.camera_eye[k];
        d2 += e * e, r2 += 0.25f * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    float dist = sqrtf(d2), radius = sqrtf(r2), m[16];
    view_proj(m, &scene, (float)width / height, fmaxf(dist - radius, 0.01f * radius), dist + radius);
    float to_light[3] = {0}, color[3] = {1, 1, 1};
    for (int k = 0; k < 3; ++k) to_light[k] = scene.camera_eye[k] - scene.camera_target[k];
    for (int i = 0; i < scene.light_count; ++i)
        if (scene.lights[i].type == DM_LIGHT_DIRECTIONAL) {
            for (int k = 0; k < 3; ++k) to_light[k] = scene.lights[i].direction[k], color[k] = scene.lights[i].color[k];
            break;
        }
    normalize3(to_light);
    glUniformMatrix4fv(glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, m);
    glUniform3fv(glGetUniformLocation(prog, "u_to_light"), 1, to_light);
    glUniform3fv(glGetUniformLocation(prog, "u_light_color"), 1, color);
    glUniform1i(glGetUniformLocation(prog, "u_albedo"), 0);

    /* 7. Draw: counter-clockwise triangles are front faces in the pack. */
    glViewport(0, 0, width, height);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glClearColor(0.05f, 0.05f, 0.06f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawElements(GL_TRIANGLES, (GLsizei)indices->index_count, GL_UNSIGNED_INT, NULL);

    /* 8. Read back: glReadPixels gives rows bottom-up, which is what dm_png_write_pixels
     *    takes (it flips them into PNG's top-down order). */
    uint8_t *rgba = malloc((size_t)width * height * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (rgba) glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    GLenum gl_error = glGetError();
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    int status = 0;
    if (!rgba || gl_error != GL_NO_ERROR || !linked) {
        fprintf(stderr, "error: OpenGL: %s (GL error 0x%04x)\n", !rgba ? "out of memory" : "draw failed",
                (unsigned)gl_error);
        status = 3;
    } else if (dm_png_write_pixels(argv[2], width, height, 4, 8, rgba, NULL, NULL, 0, &err) != DM_OK) {
        fprintf(stderr, "error: %s\n", err.detail);
        status = 4;
    } else {
        printf("%s: %dx%d, %lld triangles\n", argv[2], width, height, (long long)indices->index_count / 3);
    }

    /* 9. Free everything, the context last. */
    free(rgba);
    glDeleteProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    glDeleteTextures(1, &tex);
    glDeleteBuffers(2, buffers);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(2, rb);
    OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
    OSMesaDestroyContext(ctx);
    dm_pack_close(&pack);
    return status;
}
