/* Headless OpenGL through EGL (PLATFORM.md §2): surfaceless Mesa needs no X server or GPU, so tests,
 * CI and benchmarks render with llvmpipe exactly as a desktop GPU would, only slower. */
#include "render/render_internal.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <string.h>

/* EGL displays are per process: two renderers share one, and eglTerminate would pull it from under
 * the other, so terminate only when the last context goes. (Renderers are single-threaded.) */
static int rnd_egl_users;

static int rnd_egl_has(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
    return 0;
}

/* The EGL error's name: a bare 0x3001 tells a user nothing. */
static const char *rnd_egl_error_name(EGLint e)
{
    switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "an EGL error";
    }
}

/* Which of the three steps failed decides the message (docs/HARD_CASES.md "Faults"): no EGL driver
 * at all (glvnd found no vendor library: __EGL_VENDOR_LIBRARY_FILENAMES, a missing Mesa), a display
 * the driver cannot initialise (no usable Gallium/DRI driver: GALLIUM_DRIVER,
 * MESA_LOADER_DRIVER_OVERRIDE), or a context of the version we need (rnd_egl_create). */
static EGLDisplay rnd_egl_open_display(struct hl_error *err)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    EGLint major = 0, minor = 0, why = EGL_SUCCESS;
    const char *tried = NULL;
    rnd_gl_driver_pin();
    if (rnd_egl_has(client, "EGL_MESA_platform_surfaceless")) {
        tried = "the surfaceless platform";
        EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor))
            return d;
        why = eglGetError();
    }
    /* Fallback: the first EGL device (e.g. a driver without the surfaceless platform). */
    PFNEGLQUERYDEVICESEXTPROC query = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    if (query && rnd_egl_has(client, "EGL_EXT_platform_device")) {
        EGLDeviceEXT dev[4];
        EGLint n = 0;
        if (query(4, dev, &n) && n > 0) {
            tried = tried ? "the surfaceless platform and the EGL devices" : "the EGL devices";
            for (EGLint i = 0; i < n; ++i) {
                EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, dev[i], NULL);
                if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor))
                    return d;
                why = eglGetError();
            }
        }
    }
    if (!tried)
        hl_fail(err, "renderer: no EGL driver loaded (EGL offers neither EGL_MESA_platform_surfaceless nor an EGL "
                     "device; is Mesa's libEGL installed, and does __EGL_VENDOR_LIBRARY_FILENAMES, if set, name "
                     "its vendor file?)");
    else
        hl_fail(err, "renderer: EGL cannot initialise a headless display on %s (%s, 0x%x): no usable GPU or "
                     "software driver (is Mesa installed? GALLIUM_DRIVER or MESA_LOADER_DRIVER_OVERRIDE set wrong?)",
                tried, rnd_egl_error_name(why), (unsigned)why);
    return EGL_NO_DISPLAY;
}

int rnd_egl_create(struct rnd_egl *e, struct hl_error *err)
{
    e->display = e->context = NULL;
    EGLDisplay d = rnd_egl_open_display(err);
    if (d == EGL_NO_DISPLAY)
        return -1;
    const char *ext = eglQueryString(d, EGL_EXTENSIONS);
    if (!rnd_egl_has(ext, "EGL_KHR_no_config_context") || !rnd_egl_has(ext, "EGL_KHR_surfaceless_context")) {
        hl_fail(err, "renderer: EGL lacks EGL_KHR_no_config_context or EGL_KHR_surfaceless_context");
        goto fail;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        hl_fail(err, "renderer: eglBindAPI(EGL_OPENGL_API) failed (EGL error 0x%x)", (unsigned)eglGetError());
        goto fail;
    }
    static const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
    EGLContext c = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (c == EGL_NO_CONTEXT) {
        EGLint why = eglGetError();
        hl_fail(err, "renderer: cannot create an OpenGL 4.5 core context (%s, 0x%x): the driver offers an older "
                     "OpenGL (is MESA_GL_VERSION_OVERRIDE set?)", rnd_egl_error_name(why), (unsigned)why);
        goto fail;
    }
    rnd_window_release_current();
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
        EGLint why = eglGetError();
        hl_fail(err, "renderer: eglMakeCurrent failed (%s, 0x%x)", rnd_egl_error_name(why), (unsigned)why);
        eglDestroyContext(d, c);
        goto fail;
    }
    e->display = d;
    e->context = c;
    rnd_current_owner = e;
    rnd_egl_users++;
    return 0;
fail:
    if (rnd_egl_users == 0)
        eglTerminate(d);
    return -1;
}

/* Who made its context current last: a struct rnd_egl or a window (render/window.c). A process
 * with both a headless context (the offline analysis, the cost model) and a window's GLX context
 * switches between them; each side asks this, because neither EGL nor GLFW knows of the other's. */
const void *rnd_current_owner;

int rnd_egl_make_current(const struct rnd_egl *e)
{
    if (rnd_current_owner == e && eglGetCurrentContext() == (EGLContext)e->context)
        return 0;
    rnd_window_release_current();
    if (!eglMakeCurrent((EGLDisplay)e->display, EGL_NO_SURFACE, EGL_NO_SURFACE, (EGLContext)e->context))
        return -1;
    rnd_current_owner = e;
    return 0;
}

void rnd_egl_release_current(void)
{
    EGLContext c = eglGetCurrentContext();
    if (c != EGL_NO_CONTEXT)
        eglMakeCurrent(eglGetCurrentDisplay(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

void rnd_egl_destroy(struct rnd_egl *e)
{
    if (!e->context)
        return;
    if (eglGetCurrentContext() == (EGLContext)e->context)
        eglMakeCurrent((EGLDisplay)e->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (rnd_current_owner == e)
        rnd_current_owner = NULL;
    eglDestroyContext((EGLDisplay)e->display, (EGLContext)e->context);
    if (--rnd_egl_users == 0)
        eglTerminate((EGLDisplay)e->display);
    e->display = e->context = NULL;
}
