#include "dm_glfw.h"

#include <stdio.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

static const char *glfw_reason(void)
{
    const char *d = NULL;
    glfwGetError(&d);
    return d ? d : "no reason given";
}

dm_result dm_glfw_create(int width, int height, const char *title, bool visible, GLFWwindow **out, dm_error *err)
{
    *out = NULL;
    if (!glfwInit())
        return dm_fail(err, DM_ERR_GL, "no display: GLFW cannot initialise (%s); is DISPLAY set? (xvfb-run -a works)",
                       glfw_reason());
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow *w = glfwCreateWindow(width, height, title, NULL, NULL);
    if (!w) {
        char reason[512];
        snprintf(reason, sizeof reason, "%s", glfw_reason());
        /* what the driver offers without the 3.3 core request, to make the message useful */
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        GLFWwindow *probe = glfwCreateWindow(16, 16, "probe", NULL, NULL);
        char offers[256] = "no context at all";
        if (probe) {
            glfwMakeContextCurrent(probe);
            const char *v = (const char *)glGetString(GL_VERSION);
            snprintf(offers, sizeof offers, "the driver offers \"%s\"", v ? v : "?");
            glfwDestroyWindow(probe);
        }
        glfwTerminate();
        return dm_fail(err, DM_ERR_GL, "no OpenGL 3.3 core context: %s (%s)", reason, offers);
    }
    glfwMakeContextCurrent(w);
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 33) {
        glfwDestroyWindow(w);
        glfwTerminate();
        return dm_fail(err, DM_ERR_GL, "no OpenGL 3.3 core context: got %d.%d", major, minor);
    }
    glfwSwapInterval(1);
    *out = w;
    return DM_OK;
}

void dm_glfw_destroy(GLFWwindow *window)
{
    if (window) glfwDestroyWindow(window);
    glfwTerminate();
}
