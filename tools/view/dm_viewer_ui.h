/* dm_viewer_ui.h — the viewer's panel, help overlay and attribution on Dear ImGui
 * (Debian's libimgui 1.86, GLFW + OpenGL3 backends), behind a C interface: the only C++
 * in the viewer. The panel edits the dm_viewer through its actions (dm_viewer.h).
 * ImGui keeps one global context: one window per process.
 */
#ifndef DM_VIEWER_UI_H
#define DM_VIEWER_UI_H

#include <stdbool.h>

#include "dm_viewer.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct GLFWwindow GLFWwindow;

/* Call after installing the window's own callbacks: ImGui chains them. */
bool dm_ui_init(GLFWwindow *window);
void dm_ui_shutdown(void);
/* Whether the panel has the mouse / keyboard (the view ignores the event then). */
bool dm_ui_wants_mouse(void);
bool dm_ui_wants_keyboard(void);
/* Builds one UI frame: the picture as background, the panel (when shown), the help
 * overlay (when shown), the attribution (when the head is shown). Then dm_ui_render. */
void dm_ui_frame(dm_viewer *v);
void dm_ui_render(void);

#ifdef __cplusplus
}
#endif
#endif
