/* The live session's keys, under Xvfb (tests/with_xvfb.sh, as ctest runs it): a second X connection
 * finds the session's window by its title and sends it key presses — + + (budget up 2 ms), V and E
 * (velocity and eccentricity terms off), G (gaze vor → head), S (selector reddy → static), R (head
 * trace recording paused: --record was given), C (a capture), then Esc — and the summary must show
 * each effect and the session must have ended before its frame limit. The sender waits for what the
 * session shows, never for a fixed time: the keys go once the title says a frame was drawn (so the
 * trace has a row before R pauses it), Esc once the capture C asked for is written; each wait is
 * bounded (120 s × HMDLOD_TEST_TIME_SCALE) and says what did not happen. */
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>
#include <dirent.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/base.h"
#include "live/live.h"
#include "tests/test_util.h"

static volatile int sender_failed;

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* The bound of every wait: far above what the session needs, even on a loaded machine. */
static double deadline_s(void) { return hl_clock_now_s() + 120.0 * tu_time_scale(); }

/* 1 when the window's name starts with prefix. */
static int name_starts(Display *d, Window w, const char *prefix)
{
    char *name = NULL;
    int match = 0;
    if (XFetchName(d, w, &name) && name) {
        match = strncmp(name, prefix, strlen(prefix)) == 0;
        XFree(name);
    }
    return match;
}

/* A top-level window whose name starts with "hmdlod live" (the title is the status line). */
static Window find_window(Display *d, Window w)
{
    if (name_starts(d, w, "hmdlod live"))
        return w;
    Window root, parent, *kids = NULL, found = 0;
    unsigned n = 0;
    if (XQueryTree(d, w, &root, &parent, &kids, &n)) {
        for (unsigned i = 0; i < n && !found; ++i)
            found = find_window(d, kids[i]);
        if (kids)
            XFree(kids);
    }
    return found;
}

/* 1 when the working folder holds a finished capture (hl_out renames it to its name when complete). */
static int capture_written(void)
{
    DIR *dir = opendir(".");
    struct dirent *e;
    int found = 0;
    while (dir && !found && (e = readdir(dir)) != NULL) {
        size_t n = strlen(e->d_name);
        found = strncmp(e->d_name, "hmdlod-capture-", 15) == 0 && n > 4 && strcmp(e->d_name + n - 4, ".png") == 0;
    }
    if (dir)
        closedir(dir);
    return found;
}

static void send_key(Display *d, Window w, KeySym sym)
{
    XKeyEvent e;
    memset(&e, 0, sizeof e);
    e.display = d;
    e.window = w;
    e.root = DefaultRootWindow(d);
    e.subwindow = None;
    e.time = CurrentTime;
    e.same_screen = True;
    e.keycode = XKeysymToKeycode(d, sym);
    e.type = KeyPress;
    XSendEvent(d, w, True, KeyPressMask, (XEvent *)&e);
    e.type = KeyRelease;
    XSendEvent(d, w, True, KeyReleaseMask, (XEvent *)&e);
    XFlush(d);
}

static void *sender_fail(Display *d, const char *what)
{
    fprintf(stderr, "key sender: %s within %.0f s\n", what, 120.0 * tu_time_scale());
    sender_failed = 1;
    if (d)
        XCloseDisplay(d);
    return NULL;
}

static void *sender(void *arg)
{
    (void)arg;
    double until = deadline_s();
    Display *d = NULL;
    while (!(d = XOpenDisplay(NULL)) && hl_clock_now_s() < until)
        sleep_ms(100);
    if (!d)
        return sender_fail(NULL, "no X connection");
    Window w = 0;
    while (!(w = find_window(d, DefaultRootWindow(d))) && hl_clock_now_s() < until)
        sleep_ms(100); /* the scene loads first */
    if (!w)
        return sender_fail(d, "no window titled 'hmdlod live…' appeared");
    /* The title becomes the status line after the first frame, whose trace row is written by then. */
    while (!name_starts(d, w, "hmdlod live: frame") && hl_clock_now_s() < until)
        sleep_ms(50);
    if (!name_starts(d, w, "hmdlod live: frame"))
        return sender_fail(d, "the window's title never showed a frame");
    /* All at once: the session takes every queued key in order at its next frame. */
    static const KeySym keys[] = {XK_plus, XK_equal, XK_v, XK_e, XK_g, XK_s, XK_r, XK_c};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i)
        send_key(d, w, keys[i]);
    /* Esc only once C's capture is on disk: sent together, Esc would end the session first. */
    while (!capture_written() && hl_clock_now_s() < until)
        sleep_ms(50);
    if (!capture_written())
        return sender_fail(d, "no capture after C");
    send_key(d, w, XK_Escape);
    XCloseDisplay(d);
    return NULL;
}

int main(void)
{
    if (!getenv("DISPLAY")) {
        printf("skip: run under tests/with_xvfb.sh (ctest does)\n");
        return 77;
    }
    char dir[] = "/tmp/hmdlod-live-keys-XXXXXX";
    if (!mkdtemp(dir) || chdir(dir) != 0) { /* C writes hmdlod-capture-NNNNNN.png here */
        perror(dir);
        return 1;
    }
    struct frm_options so;
    frm_options_defaults(&so);
    so.scene = "field";
    so.object_count = 10;
    so.display = "vive";
    so.render_scale = 0.1;
    struct liv_options o;
    liv_options_defaults(&o);
    o.session = &so;
    o.device = "none";
    o.frames = 100000; /* Esc ends it long before */
    o.window_w_px = 160, o.window_h_px = 90;
    o.record_path = "head.csv";
    o.quiet_status = 1;
    pthread_t th;
    CHECK(pthread_create(&th, NULL, sender, NULL) == 0);
    struct liv_summary s;
    struct hl_error err = {""};
    int rc = liv_run(&o, &s, &err);
    pthread_join(th, NULL);
    if (rc != 0)
        fprintf(stderr, "live: %s\n", err.msg);
    CHECK(rc == 0);
    CHECK(!sender_failed);
    liv_summary_print(stdout, &s);
    CHECK(s.frames > 0 && s.frames < o.frames);          /* Esc */
    CHECK_NEAR(s.budget_ms, 1000.0 / 90.0 + 2.0, 1e-9);  /* + and = */
    CHECK(s.velocity_term == 0 && s.eccentricity_term == 0);
    CHECK(strcmp(s.gaze, "head") == 0);
    CHECK(strcmp(s.selector, "static") == 0);
    /* C wrote one capture; R paused the trace, so it has fewer rows than frames. */
    int captures = 0;
    FILE *ls = popen("ls", "r");
    char line[256];
    while (ls && fgets(line, sizeof line, ls)) {
        if (strncmp(line, "hmdlod-capture-", 15) == 0) {
            ++captures;
            line[strcspn(line, "\n")] = '\0';
            remove(line);
        }
    }
    if (ls)
        pclose(ls);
    CHECK(captures == 1);
    long rows = -1;
    FILE *f = fopen("head.csv", "r");
    CHECK(f != NULL);
    while (f && fgets(line, sizeof line, f))
        ++rows;
    if (f)
        fclose(f);
    printf("captures %d, head trace rows %ld of %ld frames\n", captures, rows, s.frames);
    CHECK(rows > 0 && rows < s.frames);
    remove("head.csv");
    if (chdir("/tmp") == 0)
        rmdir(dir);
    return tu_finish("test_live_keys");
}
