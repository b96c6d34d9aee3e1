/* render/flip: LDR-FLIP — known answers (identical images, two uniform colours, a one-pixel change
 * kept inside its filter's reach and inside its eye, bad arguments) and real captures of `hmdlod
 * replay` compared with NVIDIA's FLIP tool (built from ../shared/oracles/flip with its build.sh into
 * the build tree, once) to 1e-3 on every pooled value it prints with -txt. The tool filters the image
 * it is given as one, so each eye is cropped into its own PNG for it; our stereo result must equal the
 * two eyes' results put side by side; replay --reference's FLIP columns must be ours on the frame and
 * the reference it writes beside it. Exits 77 after the known answers when g++, the oracle's source
 * or the hmdlod program is absent. */
#include "render/render.h"
#include "test_util.h"

#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define ORACLE_TOL 1e-3
#define PI 3.14159265358979323846

/* ---- known answers ---------------------------------------------------------------------------- */
static void fill(uint8_t *rgba, size_t pixels, uint8_t r, uint8_t g, uint8_t b)
{
    for (size_t i = 0; i < pixels; ++i)
        rgba[4 * i] = r, rgba[4 * i + 1] = g, rgba[4 * i + 2] = b, rgba[4 * i + 3] = 255;
}

/* CIELAB of an sRGB byte triple with the Hunt adjustment, from the textbook formulas (not flip.c's). */
static void hunt_lab(const uint8_t c[3], double lab[3])
{
    double lin[3];
    for (int i = 0; i < 3; ++i) {
        double v = c[i] / 255.0;
        lin[i] = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
    }
    double x = (0.4124 * lin[0] + 0.3576 * lin[1] + 0.1805 * lin[2]) / 0.95047;
    double y = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2];
    double z = (0.0193 * lin[0] + 0.1192 * lin[1] + 0.9505 * lin[2]) / 1.08883;
    double f[3], t[3] = {x, y, z};
    for (int i = 0; i < 3; ++i)
        f[i] = t[i] > 216.0 / 24389.0 ? cbrt(t[i]) : (24389.0 / 27.0 * t[i] + 16.0) / 116.0;
    lab[0] = 116.0 * f[1] - 16.0;
    lab[1] = lab[0] / 100.0 * 500.0 * (f[0] - f[1]);
    lab[2] = lab[0] / 100.0 * 200.0 * (f[1] - f[2]);
}

static double hyab(const double a[3], const double b[3])
{
    return fabs(a[0] - b[0]) + hypot(a[1] - b[1], a[2] - b[2]);
}

/* The error between two uniform images: no edges or points, so the colour error alone, remapped. */
static double uniform_error(const uint8_t a[3], const uint8_t b[3])
{
    static const uint8_t green[3] = {0, 255, 0}, blue[3] = {0, 0, 255};
    double la[3], lb[3], lg[3], lbl[3];
    hunt_lab(a, la), hunt_lab(b, lb), hunt_lab(green, lg), hunt_lab(blue, lbl);
    double cmax = pow(hyab(lg, lbl), 0.7), pc = 0.4 * cmax, c = pow(hyab(la, lb), 0.7);
    return c < pc ? c * 0.95 / pc : 0.95 + (c - pc) / (cmax - pc) * 0.05;
}

static void test_known_answers(void)
{
    enum { W = 96, H = 40, EW = W / 2 };
    struct hl_error err = {""};
    uint8_t *a = malloc(W * H * 4), *b = malloc(W * H * 4);
    float *map = malloc(W * H * sizeof *map);
    for (int i = 0; i < W * H; ++i) /* a pattern, so the feature detector has edges to see */
        a[4 * i] = (uint8_t)(i * 37 % 251), a[4 * i + 1] = (uint8_t)(i * 11 % 256), a[4 * i + 2] = (uint8_t)(i % 7 * 30),
        a[4 * i + 3] = 255;
    memcpy(b, a, W * H * 4);
    struct rnd_flip_result r;

    /* Identical images: 0 everywhere, whatever the alpha says. */
    for (int i = 0; i < W * H; ++i)
        b[4 * i + 3] = (uint8_t)i;
    CHECK(rnd_flip_compute(b, a, W, H, 2, 67.0, &r, map, &err) == 0);
    int nonzero = 0;
    for (int i = 0; i < W * H; ++i)
        nonzero += map[i] != 0.0f;
    CHECK(nonzero == 0);
    CHECK(r.mean == 0.0 && r.weighted_median == 0.0 && r.weighted_q1 == 0.0 && r.weighted_q3 == 0.0);
    CHECK(r.min == 0.0 && r.max == 0.0);

    /* Two uniform colours, one eye and two: the remapped HyAB distance of their Hunt-adjusted CIELAB,
     * the same at every pixel (the filters keep a flat image flat), and the pooled values with it. */
    static const uint8_t colours[][2][3] = {
        {{0, 0, 0}, {255, 255, 255}},    /* above pc: the (pt, 1] branch */
        {{120, 80, 40}, {124, 80, 40}},  /* a small step: the [0, pt) branch */
        {{200, 30, 30}, {30, 30, 200}},  /* red against blue */
    };
    for (size_t k = 0; k < sizeof colours / sizeof colours[0]; ++k) {
        fill(a, W * H, colours[k][0][0], colours[k][0][1], colours[k][0][2]);
        fill(b, W * H, colours[k][1][0], colours[k][1][1], colours[k][1][2]);
        double want = uniform_error(colours[k][0], colours[k][1]);
        for (int eyes = 1; eyes <= 2; ++eyes) {
            CHECK(rnd_flip_compute(b, a, W, H, eyes, 67.0, &r, map, &err) == 0);
            /* The textbook sRGB matrix and white are rounded to 4 and 5 digits: 1e-4 is their reach. */
            CHECK_NEAR(r.mean, want, 1e-4);
            CHECK_NEAR(r.min, want, 1e-4);
            CHECK_NEAR(r.max, want, 1e-4);
            CHECK_NEAR(r.max - r.min, 0.0, 1e-12);
            CHECK_NEAR(r.weighted_median, want, 1e-4);
            CHECK_NEAR(map[W * H / 2 + 7], want, 1e-4);
        }
        printf("uniform (%d,%d,%d) vs (%d,%d,%d): FLIP %.6f, from the formulas %.6f\n", colours[k][0][0],
               colours[k][0][1], colours[k][0][2], colours[k][1][0], colours[k][1][1], colours[k][1][2], r.mean, want);
        struct rnd_flip_result swapped; /* symmetric in the two images */
        CHECK(rnd_flip_compute(a, b, W, H, 2, 67.0, &swapped, NULL, &err) == 0);
        CHECK(swapped.mean == r.mean && swapped.max == r.max);
    }

    /* One pixel changed in the left eye, 3 px from its seam: error at the pixel, none beyond the
     * spatial filter's reach (⌈3·√(0.04/2π²)·ppd⌉ px, the widest Gaussian's 3σ; 5 px at 30 px/deg,
     * the feature detector's ⌈3·0.041·ppd⌉ = 4 px inside it) and none at all in the right eye,
     * although the pixel is within reach of the seam. */
    for (int i = 0; i < W * H; ++i) /* a smooth gradient */
        a[4 * i] = (uint8_t)(60 + i % W), a[4 * i + 1] = (uint8_t)(40 + i / W * 2), a[4 * i + 2] = 90, a[4 * i + 3] = 255;
    memcpy(b, a, W * H * 4);
    const double ppd = 30.0;
    const int px = EW - 3, py = 20, reach = (int)ceil(3.0 * sqrt(0.04 / (2.0 * PI * PI)) * ppd);
    CHECK(reach == 5);
    b[4 * (py * W + px)] = 250, b[4 * (py * W + px) + 2] = 10;
    CHECK(rnd_flip_compute(b, a, W, H, 2, ppd, &r, map, &err) == 0);
    CHECK(map[py * W + px] > 0.1f);
    int outside = 0, right = 0, inside = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int near = abs(x - px) <= reach && abs(y - py) <= reach;
            outside += !near && map[y * W + x] != 0.0f;
            inside += near && map[y * W + x] > 0.0f;
            right += x >= EW && map[y * W + x] != 0.0f;
        }
    CHECK(outside == 0);
    CHECK(right == 0);
    CHECK(inside >= 9); /* at least the pixel's own 3 × 3 */
    printf("one pixel changed: %d pixels with error, all within %d px and in its eye; max %.4f\n", inside, reach, r.max);
    CHECK((float)r.max == map[py * W + px] && r.min == 0.0 && r.mean > 0.0);
    /* Seen as one image, the change reaches across the middle. */
    CHECK(rnd_flip_compute(b, a, W, H, 1, ppd, &r, map, &err) == 0);
    CHECK(map[py * W + EW] > 0.0f);

    /* Bad arguments: −1 and a message. */
    const double bad_ppd[] = {0.0, -67.0, NAN, INFINITY};
    for (size_t k = 0; k < sizeof bad_ppd / sizeof bad_ppd[0]; ++k) {
        err.msg[0] = 0;
        CHECK(rnd_flip_compute(b, a, W, H, 2, bad_ppd[k], &r, NULL, &err) == -1 && err.msg[0]);
    }
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(NULL, a, W, H, 2, 67.0, &r, NULL, &err) == -1 && err.msg[0]);
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(b, NULL, W, H, 2, 67.0, &r, NULL, &err) == -1 && err.msg[0]);
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(b, a, W, H, 2, 67.0, NULL, NULL, &err) == -1 && err.msg[0]);
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(b, a, 0, H, 1, 67.0, &r, NULL, &err) == -1 && err.msg[0]);
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(b, a, W, -1, 1, 67.0, &r, NULL, &err) == -1 && err.msg[0]);
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(b, a, W - 1, H, 2, 67.0, &r, NULL, &err) == -1 && err.msg[0]);
    err.msg[0] = 0;
    CHECK(rnd_flip_compute(b, a, W, H, 3, 67.0, &r, NULL, &err) == -1 && err.msg[0]);
    printf("bad arguments: e.g. \"%s\"\n", err.msg);
    /* A 1-pixel image and a tiny ppd (the feature Gaussian's tails underflow) stay finite. */
    CHECK(rnd_flip_compute(b, a, 1, 1, 1, 67.0, &r, NULL, &err) == 0 && r.mean == 0.0);
    CHECK(rnd_flip_compute(b, a, W, H, 2, 0.01, &r, map, &err) == 0 && isfinite(r.mean) && isfinite(map[0]));
    free(a);
    free(b);
    free(map);
}

/* ---- NVIDIA's tool on real captures -------------------------------------------------------------- */
static uint8_t *png_read_rgba(const char *path, int *w, int *h)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, path))
        return NULL;
    im.format = PNG_FORMAT_RGBA;
    uint8_t *buf = malloc(PNG_IMAGE_SIZE(im));
    if (!buf || !png_image_finish_read(&im, NULL, buf, 0, NULL)) {
        png_image_free(&im);
        free(buf);
        return NULL;
    }
    *w = (int)im.width, *h = (int)im.height;
    return buf;
}

static uint8_t *crop(const uint8_t *rgba, int w, int h, int x0, int cw)
{
    uint8_t *c = malloc((size_t)cw * (size_t)h * 4);
    for (int y = 0; y < h; ++y)
        memcpy(c + (size_t)y * cw * 4, rgba + ((size_t)y * w + x0) * 4, (size_t)cw * 4);
    return c;
}

/* The tool's six pooled values (mean, weighted median, 1st and 3rd weighted quartile, min, max) for
 * two PNGs; 0 or −1. */
static int run_tool(const char *tool, const char *dir, const char *name, const char *ref_png, const char *test_png,
                    double ppd, double v[6])
{
    char cmd[20000], txt[4200];
    snprintf(cmd, sizeof cmd, "OMP_NUM_THREADS=1 '%s' -r '%s' -t '%s' -ppd %.9g -d '%s' -b '%s' -txt -nerm -v 0 >/dev/null", tool,
             ref_png, test_png, ppd, dir, name);
    if (system(cmd) != 0)
        return -1;
    snprintf(txt, sizeof txt, "%s/%s.txt", dir, name);
    FILE *f = fopen(txt, "r");
    if (!f)
        return -1;
    static const char *const fmt[6] = {" Mean: %lf", " Weighted median: %lf", " 1st weighted quartile: %lf",
                                       " 3rd weighted quartile: %lf", " Min: %lf", " Max: %lf"};
    int got = 0;
    for (int k = 0; k < 6; ++k)
        got += fscanf(f, fmt[k], &v[k]) == 1;
    fclose(f);
    return got == 6 ? 0 : -1;
}

static double worst_difference;

/* Ours (one image, eyes = 1) against the tool on the same pair; prints both, checks each to 1e-3. */
static void compare(const char *tool, const char *dir, const char *label, const uint8_t *ref, const uint8_t *test, int w,
                    int h, double ppd, float *map)
{
    char rp[4200], tp[4200], name[128];
    struct hl_error err = {""};
    snprintf(name, sizeof name, "%s", label);
    for (char *c = name; *c; ++c)
        if (*c == ' ' || *c == '/')
            *c = '_';
    snprintf(rp, sizeof rp, "%s/%s_ref.png", dir, name);
    snprintf(tp, sizeof tp, "%s/%s_test.png", dir, name);
    CHECK(rnd_png_write(rp, ref, w, h, &err) == 0);
    CHECK(rnd_png_write(tp, test, w, h, &err) == 0);
    double o[6];
    if (run_tool(tool, dir, name, rp, tp, ppd, o) != 0) {
        printf("%s: the FLIP tool failed\n", label);
        CHECK(0);
        return;
    }
    struct rnd_flip_result r;
    CHECK(rnd_flip_compute(test, ref, w, h, 1, ppd, &r, map, &err) == 0);
    double ours[6] = {r.mean, r.weighted_median, r.weighted_q1, r.weighted_q3, r.min, r.max};
    printf("%-28s ppd %6.2f  ours   mean %.6f  median %.6f  q1 %.6f  q3 %.6f  min %.6f  max %.6f\n", label, ppd,
           ours[0], ours[1], ours[2], ours[3], ours[4], ours[5]);
    printf("%-28s ppd %6.2f  NVIDIA mean %.6f  median %.6f  q1 %.6f  q3 %.6f  min %.6f  max %.6f\n", label, ppd, o[0],
           o[1], o[2], o[3], o[4], o[5]);
    for (int k = 0; k < 6; ++k) {
        CHECK_NEAR(ours[k], o[k], ORACLE_TOL);
        if (fabs(ours[k] - o[k]) > worst_difference)
            worst_difference = fabs(ours[k] - o[k]);
    }
}

/* One stereo pair: each eye and the whole image against the tool, then our stereo result against
 * the eyes' (the same pixels, pooled together). */
static void compare_pair(const char *tool, const char *dir, const char *label, const char *ref_png,
                         const char *test_png, double ppd, double min_mean)
{
    int w = 0, h = 0, tw = 0, th = 0;
    uint8_t *ref = png_read_rgba(ref_png, &w, &h), *test = png_read_rgba(test_png, &tw, &th);
    CHECK(ref && test && w == tw && h == th && w % 2 == 0);
    if (!ref || !test || w != tw || h != th || w % 2 != 0) {
        free(ref), free(test);
        return;
    }
    CHECK(memcmp(ref, test, (size_t)w * h * 4) != 0); /* the frames really differ */
    int ew = w / 2;
    float *eye_map[2], *whole = malloc((size_t)w * h * sizeof *whole), *stereo = malloc((size_t)w * h * sizeof *stereo);
    char l[128];
    for (int e = 0; e < 2; ++e) {
        uint8_t *rc = crop(ref, w, h, e * ew, ew), *tc = crop(test, w, h, e * ew, ew);
        eye_map[e] = malloc((size_t)ew * h * sizeof *eye_map[e]);
        snprintf(l, sizeof l, "%s %s eye", label, e == 0 ? "left" : "right");
        compare(tool, dir, l, rc, tc, ew, h, ppd, eye_map[e]);
        free(rc), free(tc);
    }
    snprintf(l, sizeof l, "%s as one image", label);
    compare(tool, dir, l, ref, test, w, h, ppd, whole);

    struct hl_error err = {""};
    struct rnd_flip_result r, eye[2];
    CHECK(rnd_flip_compute(test, ref, w, h, 2, ppd, &r, stereo, &err) == 0);
    int mismatches = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            mismatches += stereo[y * w + x] != eye_map[x / ew][y * ew + x % ew];
    CHECK(mismatches == 0);
    for (int e = 0; e < 2; ++e) {
        uint8_t *rc = crop(ref, w, h, e * ew, ew), *tc = crop(test, w, h, e * ew, ew);
        CHECK(rnd_flip_compute(tc, rc, ew, h, 1, ppd, &eye[e], NULL, &err) == 0);
        free(rc), free(tc);
    }
    CHECK_NEAR(r.mean, 0.5 * (eye[0].mean + eye[1].mean), 1e-12);
    CHECK(r.max == fmax(eye[0].max, eye[1].max) && r.min == fmin(eye[0].min, eye[1].min));
    printf("%-28s ppd %6.2f  stereo mean %.6f  median %.6f  q1 %.6f  q3 %.6f  max %.6f (eyes filtered apart)\n",
           label, ppd, r.mean, r.weighted_median, r.weighted_q1, r.weighted_q3, r.max);
    CHECK(r.mean > min_mean);
    free(eye_map[0]), free(eye_map[1]), free(whole), free(stereo), free(ref), free(test);
}

/* The value of column `name` in frame `frame`'s row of a frames.csv, found by the header; NAN if absent. */
static double csv_value(const char *csv, long frame, const char *name)
{
    const char *cell = tu_csv_cell(csv, frame, name);
    return cell && *cell != ',' && *cell != '\n' ? strtod(cell, NULL) : NAN;
}

/* `hmdlod replay --reference 1`: frames.csv's FLIP columns are rnd_flip_compute of the capture against
 * the reference written beside it, both eyes apart, at the ppd summary.json names; that pair is
 * also checked against the tool. */
static void check_replay_reference(const char *tool, const char *dir)
{
    char path[4200], cap[4200], ref[4200];
    snprintf(path, sizeof path, "%s/refrun/summary.json", dir);
    size_t size = 0;
    char *json = tu_read_file(path, &size);
    snprintf(path, sizeof path, "%s/refrun/frames.csv", dir);
    char *csv = tu_read_file(path, &size);
    CHECK(json && csv);
    const char *at = json ? strstr(json, "\"flip\"") : NULL;
    const char *ppd_at = at ? strstr(at, "\"ppd\":") : NULL;
    double ppd = ppd_at ? strtod(ppd_at + 6, NULL) : NAN;
    CHECK(isfinite(ppd) && ppd > 0.0);
    snprintf(cap, sizeof cap, "%s/refrun/frame_000001.png", dir);
    snprintf(ref, sizeof ref, "%s/refrun/frame_000001_reference.png", dir);
    int w = 0, h = 0, rw = 0, rh = 0;
    uint8_t *test = png_read_rgba(cap, &w, &h), *reference = png_read_rgba(ref, &rw, &rh);
    CHECK(test && reference && w == rw && h == rh);
    if (csv && test && reference && isfinite(ppd) && w == rw && h == rh) {
        struct hl_error err = {""};
        struct rnd_flip_result r;
        CHECK(rnd_flip_compute(test, reference, w, h, 2, ppd, &r, NULL, &err) == 0);
        double mean = csv_value(csv, 1, "flip_mean"), median = csv_value(csv, 1, "flip_median"),
               max = csv_value(csv, 1, "flip_max");
        printf("replay --reference frame 1   ppd %6.2f  frames.csv mean %.6f  median %.6f  max %.6f\n", ppd, mean,
               median, max);
        CHECK_NEAR(mean, r.mean, 1e-6);
        CHECK_NEAR(median, r.weighted_median, 1e-6);
        CHECK_NEAR(max, r.max, 1e-6);
        CHECK(isnan(csv_value(csv, 1, "no_such_column")));
        compare_pair(tool, dir, "replay reference frame 1", ref, cap, ppd, 0.005);
    }
    free(test), free(reference), free(json), free(csv);
}

/* Where this program lives: the oracle is built beside it, in the build tree, and kept. */
static int exe_dir(char *out, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", out, size - 1);
    if (n <= 0)
        return -1;
    out[n] = 0;
    char *slash = strrchr(out, '/');
    if (!slash)
        return -1;
    *slash = 0;
    return 0;
}

/* 1 when the oracle was compared, 0 when skipped (with a message). */
static int test_against_nvidia(void)
{
    const char *bin = getenv("HMDLOD_BIN");
    if (!bin || access(bin, X_OK) != 0) {
        printf("skip: HMDLOD_BIN is unset or not a program; no captures to compare with NVIDIA's FLIP\n");
        return 0;
    }
    if (system("command -v g++ >/dev/null 2>&1") != 0) {
        printf("skip: g++ is absent, NVIDIA's FLIP tool cannot be built (build-essential)\n");
        return 0;
    }
    const char *build_sh = tu_shared_path("oracles/flip/build.sh");
    if (!build_sh)
        return 0;
    char build_sh_path[4096], tool_dir[4096], tool[4200], cmd[16384];
    snprintf(build_sh_path, sizeof build_sh_path, "%s", build_sh);
    if (!tu_shared_path("oracles/flip/cpp/tool/FLIP-tool.cpp"))
        return 0;
    CHECK(exe_dir(tool_dir, sizeof tool_dir - 16) == 0);
    strcat(tool_dir, "/flip-oracle");
    snprintf(tool, sizeof tool, "%s/flip", tool_dir);
    snprintf(cmd, sizeof cmd, "bash '%s' '%s' >/dev/null", build_sh_path, tool_dir);
    if (system(cmd) != 0 || access(tool, X_OK) != 0) {
        printf("NVIDIA's FLIP tool did not build (%s)\n", cmd);
        CHECK(0);
        return 1;
    }

    char dir[] = "/tmp/hmdlod-test-flip-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    /* Two frames of the field at a quarter of the Vive's pixels: full detail, Reddy's selection with
     * its acuity halved (at full acuity it keeps every object finest in these still frames) and
     * static at 100000 px per triangle (coarse everywhere: a large error). */
    static const struct { const char *name, *args; } runs[] = {
        {"none", "--selector none"},
        {"reddy", "--selector reddy --acuity-scale 0.5"},
        {"static", "--selector static --static-px 100000"},
        {"refrun", "--selector static --static-px 100000 --reference 1"},
    };
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; ++k) {
        snprintf(cmd, sizeof cmd,
                 "'%s' replay --scene field --display vive %s --frames 2 --capture 1 --render-scale 0.25 --quiet "
                 "--out '%s/%s' >/dev/null",
                 bin, runs[k].args, dir, runs[k].name);
        CHECK(system(cmd) == 0);
    }
    char none1[4200], reddy1[4200], static0[4200], static1[4200];
    snprintf(none1, sizeof none1, "%s/none/frame_000001.png", dir);
    snprintf(reddy1, sizeof reddy1, "%s/reddy/frame_000001.png", dir);
    snprintf(static0, sizeof static0, "%s/static/frame_000000.png", dir);
    snprintf(static1, sizeof static1, "%s/static/frame_000001.png", dir);
    char none0[4200], reddy0[4200];
    snprintf(none0, sizeof none0, "%s/none/frame_000000.png", dir);
    snprintf(reddy0, sizeof reddy0, "%s/reddy/frame_000000.png", dir);

    /* The Vive's pixels per degree at the centre of its eye image at render scale 1 (≈ 7.1: the
     * filters reach a pixel or two; replay --reference uses the same formula at its own scale, ≈ 1.8
     * here, where FLIP is nearly a per-pixel colour difference) and the tool's default, ≈ 67. */
    struct hl_error err = {""};
    struct hmd_profile vive;
    CHECK(hmd_profile_load("vive", &vive, &err) == 0);
    struct hmd_eye eye = hmd_eye_frustum(&vive, HMD_EYE_LEFT);
    double vive_ppd = vive.eye_width_px / (eye.tan_left + eye.tan_right) / HL_DEG_PER_RAD;

    compare_pair(tool, dir, "reddy/none frame 1", none1, reddy1, RND_FLIP_DEFAULT_PPD, 1e-4);
    compare_pair(tool, dir, "static/none frame 1", none1, static1, RND_FLIP_DEFAULT_PPD, 0.005);
    compare_pair(tool, dir, "static/none frame 0 (Vive)", none0, static0, vive_ppd, 0.005);
    compare_pair(tool, dir, "reddy/none frame 0 (Vive)", none0, reddy0, vive_ppd, 1e-4);
    check_replay_reference(tool, dir);
    printf("largest difference from NVIDIA's tool: %.2e (tolerance %.0e)\n", worst_difference, ORACLE_TOL);

    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0);
    return 1;
}

int main(void)
{
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    test_known_answers();
    int compared = test_against_nvidia();
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("time: %.1f s\n", (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
    int rc = tu_finish("flip");
    return rc == 0 && !compared ? 77 : rc;
}
