/* Under AddressSanitizer only: keeps Mesa's software driver (llvmpipe, swrast_dri.so) loaded for the
 * life of the process. Its globals hold ~240 bytes allocated on the first draw and never freed;
 * eglTerminate and glfwTerminate dlclose the driver before LeakSanitizer runs at exit, after which
 * those blocks read as leaks from "<unknown module>" that no suppression can name (PLATFORM.md §4,
 * fix 1, verified there to still catch a deliberate leak of our own). The test programs pin it the
 * same way in main; this does it for the hmdlod program, which the CLI, live and bench tests run
 * with LeakSanitizer on. Normal builds compile this to nothing. */
#include "render/render_internal.h"

#if defined(__SANITIZE_ADDRESS__)
#define RND_PIN_DRIVER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RND_PIN_DRIVER 1
#endif
#endif

#ifdef RND_PIN_DRIVER
#include <dlfcn.h>
#endif

void rnd_gl_driver_pin(void)
{
#ifdef RND_PIN_DRIVER
    static int pinned;
    if (!pinned) {
        pinned = 1;
        /* Absent (another driver, another distribution): nothing to pin, nothing lost. */
        (void)dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_NOW | RTLD_NODELETE);
    }
#endif
}
