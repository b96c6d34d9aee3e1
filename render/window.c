/* The GLFW window of a live session (DESIGN.md: render/ holds the EGL and the GLFW contexts): a desk
 * window or fullscreen on the headset's output, its keys and mouse, and the monitors GLFW sees.
 * The context is GLX under X (PLATFORM.md §3: GLFW's EGL context API works under Xvfb too but swaps
 * about 8× slower); the renderer's GL calls go through glvnd's libOpenGL, which dispatches to
 * whichever context is current, so the same renderer code draws in either. */
#include "render/render_internal.h"

#define GLFW_INCLUDE_NONE
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <stdlib.h>
#include <string.h>

enum { RND_KEY_QUEUE = 32 };

struct rnd_window {
    GLFWwindow *glfw;
    int keys[RND_KEY_QUEUE];
    int key_head, key_count;
    double mouse_x, mouse_y, mouse_dx, mouse_dy;
    int mouse_known, dragging;
};

static int rnd_glfw_users;
static char rnd_glfw_last_error[256];

static void rnd_glfw_error(int code, const char *text)
{
    snprintf(rnd_glfw_last_error, sizeof rnd_glfw_last_error, "%s (GLFW error 0x%x)", text ? text : "?", code);
}

static int rnd_glfw_init(struct hl_error *err)
{
    if (rnd_glfw_users > 0) {
        rnd_glfw_users++;
        return 0;
    }
    rnd_gl_driver_pin();
    glfwSetErrorCallback(rnd_glfw_error);
    rnd_glfw_last_error[0] = '\0';
    if (!glfwInit())
        return hl_fail(err, "window: GLFW cannot start: %s (is DISPLAY set? headless: run under xvfb-run -a)",
                       rnd_glfw_last_error[0] ? rnd_glfw_last_error : "unknown error");
    rnd_glfw_users = 1;
    return 0;
}

static void rnd_glfw_release(void)
{
    if (rnd_glfw_users > 0 && --rnd_glfw_users == 0)
        glfwTerminate();
}

/* A headset's panel driven as one monitor: its mode is both eyes side by side (or stacked) of a
 * built-in profile, or its EDID name says so. GLFW 3.3 names X outputs by the monitor's EDID name
 * when RandR gives one, else by the connector. */
static int rnd_looks_like_headset(const char *name, int w, int h, int width_mm)
{
    static const char *const words[] = {"htc", "vive", "rift", "oculus", "index", "valve", "psvr", "sony vr",
                                        "hdk", "osvr", "pimax", "varjo", "reverb", "wmr", NULL};
    char lower[128];
    size_t n = 0;
    for (; name && name[n] && n + 1 < sizeof lower; ++n)
        lower[n] = (char)((name[n] >= 'A' && name[n] <= 'Z') ? name[n] + 32 : name[n]);
    lower[n] = '\0';
    for (int i = 0; words[i]; ++i)
        if (strstr(lower, words[i]))
            return 1;
    for (int i = 0; i < hmd_builtin_count(); ++i) {
        const struct hmd_profile *p = hmd_builtin_at(i);
        int side_by_side = w == 2 * p->eye_width_px && h == p->eye_height_px;
        int portrait = w == p->eye_height_px && h == 2 * p->eye_width_px; /* panels mounted rotated */
        if ((side_by_side || portrait) && (width_mm == 0 || width_mm < 200))
            return 1;
    }
    return 0;
}

int rnd_monitor_list(struct rnd_monitor_info *out, int max, struct hl_error *err)
{
    if (rnd_glfw_init(err) != 0)
        return -1;
    int count = 0;
    GLFWmonitor **mons = glfwGetMonitors(&count);
    int n = 0;
    for (int i = 0; i < count && n < max; ++i, ++n) {
        struct rnd_monitor_info *m = &out[n];
        memset(m, 0, sizeof *m);
        const char *name = glfwGetMonitorName(mons[i]);
        snprintf(m->name, sizeof m->name, "%s", name ? name : "?");
        const GLFWvidmode *mode = glfwGetVideoMode(mons[i]);
        if (mode) {
            m->width_px = mode->width;
            m->height_px = mode->height;
            m->refresh_hz = mode->refreshRate;
        }
        glfwGetMonitorPos(mons[i], &m->x_px, &m->y_px);
        glfwGetMonitorPhysicalSize(mons[i], &m->width_mm, &m->height_mm);
        m->looks_like_headset = rnd_looks_like_headset(m->name, m->width_px, m->height_px, m->width_mm);
    }
    rnd_glfw_release();
    return n;
}

static void rnd_on_key(GLFWwindow *g, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    struct rnd_window *w = glfwGetWindowUserPointer(g);
    if (!w || action != GLFW_PRESS)
        return;
    int k = 0;
    if (key == GLFW_KEY_ESCAPE)
        k = RND_KEY_ESCAPE;
    else if (key == GLFW_KEY_UP)
        k = RND_KEY_UP;
    else if (key == GLFW_KEY_DOWN)
        k = RND_KEY_DOWN;
    else if (key == GLFW_KEY_LEFT)
        k = RND_KEY_LEFT;
    else if (key == GLFW_KEY_RIGHT)
        k = RND_KEY_RIGHT;
    else if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD)
        k = '+';
    else if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT)
        k = '-';
    else if ((key >= GLFW_KEY_A && key <= GLFW_KEY_Z) || (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) ||
             key == GLFW_KEY_SPACE)
        k = key; /* GLFW's codes for these are their ASCII (upper case) */
    if (k && w->key_count < RND_KEY_QUEUE) {
        w->keys[(w->key_head + w->key_count) % RND_KEY_QUEUE] = k;
        w->key_count++;
    }
}

/* Mouse look: the pointer's motion while the left button is held (so the desktop stays usable). */
static void rnd_on_cursor(GLFWwindow *g, double x, double y)
{
    struct rnd_window *w = glfwGetWindowUserPointer(g);
    if (!w)
        return;
    if (w->mouse_known && w->dragging) {
        w->mouse_dx += x - w->mouse_x;
        w->mouse_dy += y - w->mouse_y;
    }
    w->mouse_x = x, w->mouse_y = y, w->mouse_known = 1;
}

static void rnd_on_button(GLFWwindow *g, int button, int action, int mods)
{
    (void)mods;
    struct rnd_window *w = glfwGetWindowUserPointer(g);
    if (w && button == GLFW_MOUSE_BUTTON_LEFT)
        w->dragging = action == GLFW_PRESS;
}

int rnd_window_create(const struct rnd_window_params *p, struct rnd_window **out, struct hl_error *err)
{
    *out = NULL;
    if (!p || p->width_px < 1 || p->height_px < 1 || p->width_px > 16384 || p->height_px > 16384)
        return hl_fail(err, "window: size out of range (1…16384 each)");
    if (rnd_glfw_init(err) != 0)
        return -1;
    struct rnd_window *w = calloc(1, sizeof *w);
    if (!w) {
        rnd_glfw_release();
        return hl_fail(err, "window: out of memory");
    }
    GLFWmonitor *monitor = NULL;
    if (p->monitor >= 0) {
        int count = 0;
        GLFWmonitor **mons = glfwGetMonitors(&count);
        if (p->monitor >= count) {
            hl_fail(err, "--monitor %d: there are %d monitors (hmdlod live --list-monitors)", p->monitor, count);
            goto fail;
        }
        monitor = mons[p->monitor];
    }
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5); /* the renderer's shaders are #version 450 */
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 0); /* the window only receives the distortion pass */
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    int width = p->width_px, height = p->height_px;
    if (monitor) {
        /* Fullscreen at the output's own mode: a headset panel must not be mode-switched. */
        const GLFWvidmode *mode = glfwGetVideoMode(monitor);
        if (mode) {
            width = mode->width, height = mode->height;
            glfwWindowHint(GLFW_REFRESH_RATE, mode->refreshRate);
        }
    }
    rnd_glfw_last_error[0] = '\0';
    w->glfw = glfwCreateWindow(width, height, p->title ? p->title : "hmdlod", monitor, NULL);
    if (!w->glfw) {
        hl_fail(err, "window: cannot create a %d×%d window with an OpenGL 4.5 core context: %s", width, height,
                rnd_glfw_last_error[0] ? rnd_glfw_last_error : "unknown error");
        goto fail;
    }
    glfwSetWindowUserPointer(w->glfw, w);
    glfwSetKeyCallback(w->glfw, rnd_on_key);
    glfwSetCursorPosCallback(w->glfw, rnd_on_cursor);
    glfwSetMouseButtonCallback(w->glfw, rnd_on_button);
    rnd_egl_release_current();
    glfwMakeContextCurrent(w->glfw);
    rnd_current_owner = w;
    *out = w;
    return 0;
fail:
    free(w);
    rnd_glfw_release();
    return -1;
}

void rnd_window_destroy(struct rnd_window *w)
{
    if (!w)
        return;
    if (w->glfw)
        glfwDestroyWindow(w->glfw);
    if (rnd_current_owner == w)
        rnd_current_owner = NULL;
    free(w);
    rnd_glfw_release();
}

int rnd_window_make_current(struct rnd_window *w)
{
    if (!w || !w->glfw)
        return -1;
    if (rnd_current_owner == w && glfwGetCurrentContext() == w->glfw)
        return 0;
    rnd_egl_release_current();
    glfwMakeContextCurrent(w->glfw);
    rnd_current_owner = w;
    return 0;
}

void rnd_window_release_current(void)
{
    if (rnd_glfw_users > 0 && glfwGetCurrentContext())
        glfwMakeContextCurrent(NULL);
}

void rnd_window_size(const struct rnd_window *w, int *width_px, int *height_px)
{
    int fw = 0, fh = 0;
    if (w && w->glfw)
        glfwGetFramebufferSize(w->glfw, &fw, &fh);
    if (width_px)
        *width_px = fw;
    if (height_px)
        *height_px = fh;
}

double rnd_window_refresh_hz(const struct rnd_window *w)
{
    GLFWmonitor *m = w && w->glfw ? glfwGetWindowMonitor(w->glfw) : NULL;
    if (!m)
        m = glfwGetPrimaryMonitor();
    const GLFWvidmode *mode = m ? glfwGetVideoMode(m) : NULL;
    return mode ? mode->refreshRate : 0.0; /* Xvfb reports 0 Hz (PLATFORM.md §3) */
}

void rnd_window_poll(struct rnd_window *w)
{
    (void)w;
    glfwPollEvents();
}

int rnd_window_should_close(const struct rnd_window *w) { return !w || !w->glfw || glfwWindowShouldClose(w->glfw); }

void rnd_window_swap(struct rnd_window *w)
{
    if (!w || !w->glfw)
        return;
    glfwSwapBuffers(w->glfw);
    /* A round trip to the X server, so that the swap's return means the server has the image:
     * without it (Mesa's software GLX posts the image and returns) the wait would surface in the
     * next frame's first GL call on the window, and the present time would be early. */
    int fw, fh;
    glfwGetFramebufferSize(w->glfw, &fw, &fh);
}

void rnd_window_set_swap_interval(struct rnd_window *w, int interval)
{
    if (rnd_window_make_current(w) == 0)
        glfwSwapInterval(interval);
}

void rnd_window_set_title(struct rnd_window *w, const char *title)
{
    if (w && w->glfw)
        glfwSetWindowTitle(w->glfw, title);
}

int rnd_window_next_key(struct rnd_window *w, int *key)
{
    if (!w || w->key_count == 0)
        return 0;
    *key = w->keys[w->key_head];
    w->key_head = (w->key_head + 1) % RND_KEY_QUEUE;
    w->key_count--;
    return 1;
}

void rnd_window_mouse_delta(struct rnd_window *w, double *dx_px, double *dy_px)
{
    *dx_px = w ? w->mouse_dx : 0.0;
    *dy_px = w ? w->mouse_dy : 0.0;
    if (w)
        w->mouse_dx = w->mouse_dy = 0.0;
}

int rnd_window_read_rgba(struct rnd_window *w, uint8_t *rgba, struct hl_error *err)
{
    int width, height;
    rnd_window_size(w, &width, &height);
    if (!rgba || rnd_window_make_current(w) != 0)
        return hl_fail(err, "window: no window or buffer");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK); /* what the last distortion pass drew, before it is swapped */
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return hl_fail(err, "window: glReadPixels failed: GL error 0x%x", (unsigned)e);
    rnd_flip_rows(rgba, width, height);
    return 0;
}
