/* hmdlod live: argument parsing around liv_run, and --list-monitors. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "render/render.h"
#include "live/live.h"

static const char live_usage[] =
    "usage: hmdlod live --display NAME|FILE --device auto|PATH|none --scene NAME|FILE [--monitor NAME|INDEX]\n"
    "                   [--windowed] [--selector NAME] [--budget-ms T] [--frames N] [--capture FILE]\n"
    "                   [--record FILE] [--yaw-degps V] [--rate HZ] [--render-scale F] [--window-size WxH]\n"
    "                   [--objects N] [--log FILE] [--gaze MODEL] [--foveation off|fixed|gaze]\n"
    "                   [--periphery-scale S] [--inset-deg R] [--blend-deg B] [--quiet]\n"
    "       hmdlod live --list-monitors\n"
    "  A live session: both eyes drawn by the same frame function as replay, then the lens distortion\n"
    "  pass (the profile's PanoTools coefficients with chromatic aberration; undistorted when it has\n"
    "  none), at the display's refresh on the wall clock. docs/live.md.\n"
    "  --display NAME|FILE  built-in display (hmdlod display list) or a JSON profile (default vive)\n"
    "  --device auto|PATH|none  head tracker: auto (default; the first supported tracker, else mouse and\n"
    "                     keys), a hidraw node, or none (mouse and keys; with --yaw-degps a scripted turn)\n"
    "  --scene NAME|FILE  built-in scene (field, auditorium, domes) or a scene file (default field)\n"
    "  --monitor NAME|INDEX  fullscreen on this output (hmdlod live --list-monitors); default: a window\n"
    "  --windowed         a window on the desktop even when --monitor is given\n"
    "  --selector NAME    none, reddy (default), static, feedback, fs, mb (as hmdlod replay)\n"
    "  --budget-ms T      frame budget in ms (default: the display's frame period)\n"
    "  --frames N         stop after N frames (default: run until Esc, the window closes or Ctrl-C)\n"
    "  --capture FILE     write the distorted output of the last frame as a PNG\n"
    "  --record FILE      write the session's head motion as a trace CSV (t_s,qw,qx,qy,qz)\n"
    "  --log FILE         one CSV row per frame: frame and display time, frame, distortion, present\n"
    "                     interval and start-to-present ms, missed slots so far, on time, triangles,\n"
    "                     head speed, tracking (docs/live.md)\n"
    "  --yaw-degps V      desk: a scripted yaw of V deg/s added to the mouse (default 0; deterministic)\n"
    "  --rate HZ          frame rate (default: the display profile's refresh)\n"
    "  --render-scale F   per-eye resolution factor in (0, 4] (default 1)\n"
    "  --objects N        objects in the field scene (default 100) or domes in domes (default 10)\n"
    "  --window-size WxH  windowed size (default: both eyes at the display's pixels, fit to the monitor)\n"
    "  --gaze MODEL       auto (vor), head or vor\n"
    "  --quiet            no status line on the terminal (the summary is still printed)\n"
    "  Keys: Esc or Q quits, S switches the selector, + and - change the budget by 1 ms, V and E toggle\n"
    "  the velocity and eccentricity terms, G switches the gaze model (vor, head), C captures a PNG, R\n"
    "  starts or stops recording the head trace; desk: drag with the left button or the arrows look.\n";

static int list_monitors(void)
{
    struct rnd_monitor_info m[16];
    struct hl_error err;
    int n = rnd_monitor_list(m, 16, &err);
    if (n < 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    printf("%-5s %-24s %-11s %-8s %-12s %s\n", "index", "name", "size", "refresh", "position", "headset?");
    for (int i = 0; i < n; ++i) {
        char size[32], pos[32], hz[16];
        snprintf(size, sizeof size, "%dx%d", m[i].width_px, m[i].height_px);
        snprintf(pos, sizeof pos, "%+d%+d", m[i].x_px, m[i].y_px);
        if (m[i].refresh_hz > 0)
            snprintf(hz, sizeof hz, "%.0f Hz", m[i].refresh_hz);
        else
            snprintf(hz, sizeof hz, "unknown");
        printf("%-5d %-24s %-11s %-8s %-12s %s\n", i, m[i].name, size, hz, pos,
               m[i].looks_like_headset ? "looks like a headset" : "-");
    }
    printf("\nOn Linux a headset's EDID usually marks it non-desktop: the X server and compositors keep it\n"
           "off the desktop, so it is not listed here. To reach it: `xrandr --prop` shows the output with\n"
           "non-desktop: 1; `xrandr --output NAME --set non-desktop 0 && xrandr --output NAME --auto\n"
           "--right-of PRIMARY` makes it a monitor (then --monitor INDEX); or use a DRM lease (Monado,\n"
           "SteamVR) instead of a desktop window. docs/live.md.\n");
    return 0;
}

/* --monitor: an index, or a name among the listed monitors. */
static int parse_monitor(const char *val, int *out)
{
    char *end = NULL;
    long v = strtol(val, &end, 10);
    if (end && *end == '\0' && end != val) {
        if (v < 0 || v > 64) {
            fprintf(stderr, "hmdlod: --monitor: %s is not a monitor index\n", val);
            return 1;
        }
        *out = (int)v;
        return 0;
    }
    struct rnd_monitor_info m[16];
    struct hl_error err;
    int n = rnd_monitor_list(m, 16, &err);
    if (n < 0) {
        fprintf(stderr, "hmdlod: --monitor %s: %s\n", val, err.msg);
        return 1;
    }
    for (int i = 0; i < n; ++i)
        if (strcmp(m[i].name, val) == 0) {
            *out = i;
            return 0;
        }
    fprintf(stderr, "hmdlod: --monitor: no monitor named '%s' (hmdlod live --list-monitors)\n", val);
    return 1;
}

int cmd_live(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(live_usage, stdout);
        fputs(app_layer_usage, stdout);
        return 0;
    }
    struct frm_options so;
    frm_options_defaults(&so);
    struct liv_options o;
    liv_options_defaults(&o);
    o.session = &so;
    int windowed = 0, quiet = 0;
    const char *monitor = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        if (!strcmp(opt, "--list-monitors"))
            return list_monitors();
        if (!strcmp(opt, "--windowed")) {
            windowed = 1;
            continue;
        }
        if (!strcmp(opt, "--quiet")) {
            quiet = 1;
            continue;
        }
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!val) {
            fprintf(stderr, "hmdlod: %s needs a value\n", opt);
            return 1;
        }
        ++i;
        double d = 0.0;
        int bad = 0;
        if (!strcmp(opt, "--display"))
            so.display = val;
        else if (!strcmp(opt, "--device"))
            o.device = val;
        else if (!strcmp(opt, "--scene"))
            so.scene = val;
        else if (!strcmp(opt, "--selector"))
            so.selector = val;
        else if (!strcmp(opt, "--monitor"))
            monitor = val;
        else if (!strcmp(opt, "--capture"))
            o.capture_path = val;
        else if (!strcmp(opt, "--record"))
            o.record_path = val;
        else if (!strcmp(opt, "--log"))
            o.log_path = val;
        else if (!strcmp(opt, "--gaze"))
            so.gaze = val;
        else if (!strcmp(opt, "--frames")) {
            if (app_parse_long(opt, val, 1, 100000000, &o.frames))
                return 1;
        } else if (!strcmp(opt, "--budget-ms")) {
            if (app_parse_double(opt, val, &d))
                return 1;
            if (!(d > 0.0)) {
                fprintf(stderr, "hmdlod: --budget-ms: %s is not a positive number of milliseconds\n", val);
                return 1;
            }
            so.budget_ms = d;
        } else if (!strcmp(opt, "--yaw-degps")) {
            if (app_parse_double(opt, val, &o.yaw_degps))
                return 1;
        } else if (!strcmp(opt, "--rate")) {
            if (app_parse_double(opt, val, &o.rate_hz))
                return 1;
            if (!(o.rate_hz >= 1.0 && o.rate_hz <= 1000.0)) {
                fprintf(stderr, "hmdlod: --rate: %s Hz is outside [1, 1000]\n", val);
                return 1;
            }
        } else if (!strcmp(opt, "--window-size")) {
            char extra = 0;
            if (sscanf(val, "%dx%d%c", &o.window_w_px, &o.window_h_px, &extra) != 2 || o.window_w_px < 2 ||
                o.window_h_px < 1 || o.window_w_px > 16384 || o.window_h_px > 16384) {
                fprintf(stderr, "hmdlod: --window-size: '%s' is not WIDTHxHEIGHT in pixels (2..16384 each)\n", val);
                return 1;
            }
        } else if (!strcmp(opt, "--objects")) {
            long n = 0;
            if (app_parse_long(opt, val, 1, 100000, &n))
                return 1;
            so.object_count = (int)n;
        } else if (!strcmp(opt, "--render-scale")) {
            if (app_parse_double(opt, val, &so.render_scale))
                return 1;
        } else if (app_parse_layer_option(opt, val, &so, &bad)) {
            if (bad)
                return 1;
        } else {
            fprintf(stderr, "hmdlod: unknown option '%s'\n%s", opt, live_usage);
            return 1;
        }
    }
    if (strcmp(o.device, "auto") != 0 && strcmp(o.device, "none") != 0 && strncmp(o.device, "/", 1) != 0) {
        fprintf(stderr, "hmdlod: --device: '%s' is not auto, none or a hidraw path such as /dev/hidraw3\n", o.device);
        return 1;
    }
    if (so.gaze && strcmp(so.gaze, "tracked") == 0) {
        fprintf(stderr, "hmdlod: --gaze tracked: live sessions have no eye tracker yet (use vor or head)\n");
        return 1;
    }
    if (monitor && !windowed && parse_monitor(monitor, &o.monitor) != 0)
        return 1;
    o.quiet_status = quiet;
    struct liv_summary summary;
    struct hl_error err;
    if (liv_run(&o, &summary, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    liv_summary_print(stdout, &summary);
    return 0;
}
