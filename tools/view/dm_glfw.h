/* dm_glfw.h — the viewer's window host: a GLFW window with an OpenGL 3.3 core context
 * made current (the interactive twin of lib/host/dm_osmesa.h; lib/render stays
 * window-free). GL entry points come from GLVND's libGL (GL_GLEXT_PROTOTYPES +
 * GL/glcorearb.h), as in the renderer, so no loader is needed.
 */
#ifndef DM_GLFW_H
#define DM_GLFW_H

#include <stdbool.h>

#include "core/dm_result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct GLFWwindow GLFWwindow;

/* Initialises GLFW, opens a width x height window (not resizable; hidden when !visible)
 * with a 3.3+ core context, makes it current and turns vsync on. Fails with DM_ERR_GL,
 * saying why: no display (GLFW cannot initialise), or no OpenGL 3.3 core context (the
 * message carries GLFW's reason and what the driver offers). Free with dm_glfw_destroy,
 * which also terminates GLFW. */
dm_result dm_glfw_create(int width, int height, const char *title, bool visible, GLFWwindow **out, dm_error *err);
void dm_glfw_destroy(GLFWwindow *window);

#ifdef __cplusplus
}
#endif
#endif
