/* Tests of the trace part of replay/: parsing rules and their messages, every truncated prefix,
 * hemisphere handling, windowed angular velocity (constant rate, gaps, spikes), the real Corbillon
 * traces when ../shared has them, the built-in clip, and the pose source. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "replay/replay.h"
#include "tests/test_util.h"

/* ---- helpers -------------------------------------------------------------------------------- */

/* A growing text buffer for generated traces. */
struct text {
    char *s;
    size_t n, cap;
};

static void text_add(struct text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char line[512];
    int k = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (k < 0)
        return;
    if (t->n + (size_t)k + 1 > t->cap) {
        t->cap = (t->cap + (size_t)k + 1) * 2;
        t->s = realloc(t->s, t->cap);
    }
    memcpy(t->s + t->n, line, (size_t)k + 1);
    t->n += (size_t)k;
}

/* Parses exactly `len` bytes from a private heap copy, so any read past the end trips ASan. */
static int parse_exact(const char *src, size_t len, const char *name, struct rpl_trace *tr, struct hl_error *err)
{
    char *copy = malloc(len ? len : 1);
    if (len)
        memcpy(copy, src, len);
    int rc = rpl_trace_parse(copy, len, name, tr, err);
    free(copy);
    return rc;
}

/* "name:<digits>:" at the start of msg; returns the line number or −1. */
static long message_line(const char *msg, const char *name)
{
    size_t k = strlen(name);
    if (strncmp(msg, name, k) != 0 || msg[k] != ':')
        return -1;
    char *end;
    long line = strtol(msg + k + 1, &end, 10);
    return (end != msg + k + 1 && *end == ':') ? line : -1;
}

static hl_quatd yaw_q(double yaw_deg)
{
    return hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw_deg * HL_RAD_PER_DEG);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ---- (a) a small valid CSV and all its prefixes ---------------------------------------------- */

static const char SMALL_CSV[] =
    "# hmdlod head trace, example\n"
    "t_s,qw,qx,qy,qz,px,py,pz,gx,gy,gz\n"
    "0.000,1,0,0,0,0,1.6,0,0,0,-1\n"
    "\n"
    "0.010,0.9999619230641713,0,0.008726535498373935,0,0.01,1.6,0,0,0,-2\n"
    "# a comment between rows\n"
    "0.020,0.9998476951563913,0,0.01745240643728351,0,0.02,1.6,0,0.1,0,-1\n"
    "0.030,-0.9996573249755573,0,-0.02617694830787315,0,0.03,1.6,0,0,0,-1\n";

static void test_small_csv(void)
{
    struct rpl_trace tr;
    struct hl_error err = {{0}};
    int rc = rpl_trace_parse(SMALL_CSV, strlen(SMALL_CSV), "small.csv", &tr, &err);
    CHECK(rc == 0);
    if (rc != 0) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    CHECK(tr.format == RPL_TRACE_HMDLOD_CSV);
    CHECK(tr.count == 4 && tr.report.rows == 4);
    CHECK(tr.position_m && tr.gaze_dir);
    CHECK_NEAR(tr.time_s[2], 0.020, 1e-15);
    CHECK_NEAR(tr.orientation[1].y, 0.008726535498373935, 1e-15);
    CHECK(tr.orientation[3].w > 0); /* flipped into the previous hemisphere */
    CHECK(tr.report.sign_flips == 1);
    CHECK_NEAR(tr.position_m[2].x, 0.02, 1e-15);
    CHECK_NEAR(tr.gaze_dir[1].z, -1.0, 1e-15); /* (0,0,−2) renormalised */
    CHECK_NEAR(hl_v3_length(tr.gaze_dir[2]), 1.0, 1e-12);
    CHECK(tr.report.gaps == 0 && tr.report.speed_outliers == 0 && tr.report.repeated_samples == 0);

    struct trk_pose pose;
    rpl_trace_sample(&tr, 0.015, &pose);
    CHECK_NEAR(hl_q_angle_rad(pose.orientation, yaw_q(1.5)), 0.0, 1e-9);
    CHECK(pose.has_position && pose.has_gaze);
    CHECK_NEAR(pose.position_m.x, 0.015, 1e-12);
    /* 1 deg per 10 ms = 100 deg/s about +Y. */
    CHECK_NEAR(pose.angular_velocity_radps.y * HL_DEG_PER_RAD, 100.0, 1e-6);
    rpl_trace_free(&tr);
    CHECK(tr.count == 0 && tr.time_s == NULL);

    /* CRLF line endings give the same trace. */
    struct text crlf = {0};
    for (const char *p = SMALL_CSV; *p; ++p) {
        if (*p == '\n')
            text_add(&crlf, "\r\n");
        else
            text_add(&crlf, "%c", *p);
    }
    rc = parse_exact(crlf.s, crlf.n, "crlf.csv", &tr, &err);
    CHECK(rc == 0 && tr.count == 4);
    if (rc == 0)
        CHECK_NEAR(tr.orientation[2].y, 0.01745240643728351, 1e-15);
    rpl_trace_free(&tr);
    free(crlf.s);

    /* Every prefix: OK only at a whole-line end (or inside a trailing comment/blank line) with ≥ 1
     * data row; otherwise "name:<line>:", and for a cut data row, that row's line. */
    size_t n = strlen(SMALL_CSV);
    int prefix_ok = 0, prefix_fail = 0, prefix_bad = 0;
    for (size_t len = 0; len <= n; ++len) {
        /* What the prefix holds. */
        size_t line = 1, data_rows = 0, line_start = 0;
        int header_seen = 0;
        for (size_t i = 0; i < len; ++i) {
            if (SMALL_CSV[i] != '\n')
                continue;
            char c = SMALL_CSV[line_start];
            if (line_start < i && c != '#') {
                if (header_seen)
                    ++data_rows;
                header_seen = 1;
            }
            ++line;
            line_start = i + 1;
        }
        int partial_is_data = len > line_start && SMALL_CSV[line_start] != '#' && header_seen;
        int partial_harmless = len == line_start || SMALL_CSV[line_start] == '#';
        int expect_ok = partial_harmless && data_rows >= 1;

        struct rpl_trace t;
        struct hl_error e = {{0}};
        int r = parse_exact(SMALL_CSV, len, "p.csv", &t, &e);
        if (expect_ok) {
            if (r == 0 && t.count == data_rows)
                ++prefix_ok;
            else {
                ++prefix_bad;
                fprintf(stderr, "prefix %zu: expected %zu rows, rc %d: %s\n", len, data_rows, r, e.msg);
            }
        } else {
            long at = r == 0 ? -1 : message_line(e.msg, "p.csv");
            if (r != 0 && at > 0 && (!partial_is_data || at == (long)line))
                ++prefix_fail;
            else {
                ++prefix_bad;
                fprintf(stderr, "prefix %zu: expected failure at line %zu, rc %d: %s\n", len, line, r, e.msg);
            }
            CHECK(t.count == 0 && t.time_s == NULL); /* nothing left allocated */
        }
        rpl_trace_free(&t);
    }
    CHECK(prefix_bad == 0);
    CHECK(prefix_ok >= 4);
    printf("prefixes: %d parse, %d fail with a line, %d wrong\n", prefix_ok, prefix_fail, prefix_bad);
}

/* ---- (b) malformed rows ---------------------------------------------------------------------- */

struct bad_case {
    const char *text;
    long line;
    const char *needle;
};

static void test_malformed(void)
{
    static const struct bad_case cases[] = {
        {"", 1, "empty input"},
        {"\n# only a comment\n", 3, "no header"},
        {"t,qw,qx,qy,qz\n0,1,0,0,0\n", 1, "unrecognised header"},
        {"t_s,qw,qx,qy,qz,px,py\n0,1,0,0,0,0,0\n", 1, "unrecognised header"},
        {"timestamp viewpoint w x y\n", 1, "unrecognised header"},
        {"t_s,qw,qx,qy,qz\n", 1, "no data rows"},
        {"t_s,qw,qx,qy,qz\n# c\n\n", 1, "no data rows"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,abc,0,0\n", 3, "column qx: not a number"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,nan,0\n", 3, "column qy: not finite"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\ninf,1,0,0,0\n", 3, "column t_s: not finite"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0,1e999\n", 3, "column qz: not finite"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,,0\n", 3, "column qy: empty field"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1.01,0,0,0\n", 3, "norm 1.01"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,0,0,0,0\n", 3, "norm 0"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0,0\n0.05,1,0,0,0\n", 4, "time goes backwards"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0,0\n0.1,1,0,0,0\n", 4, "time does not increase"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0\n", 3, "expected 5 columns, found 4"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0,0,0\n", 3, "expected 5 columns, found 6"},
        {"t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0,0,0", 3, "truncated last row"},
        {"t_s,qw,qx,qy,qz,gx,gy,gz\n0,1,0,0,0,0,0,-1\n0.1,1,0,0,0,0,0,0\n", 3, "gaze vector has zero length"},
        {"timestamp viewpoint w x y z\n0.0 0 1 0 0 0\n0.1 0 1 0 0\n", 3, "expected 6 columns, found 5"},
        {"timestamp viewpoint w x y z\n0.0 0 1 0 0 0\n0.0 0 1 0 0 0\n", 3, "time does not increase"},
        {"timestamp viewpoint w x y z\n0.0 x 1 0 0 0\n", 2, "column viewpoint: not a number"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        struct rpl_trace tr;
        struct hl_error err = {{0}};
        int rc = parse_exact(cases[i].text, strlen(cases[i].text), "bad.csv", &tr, &err);
        long line = message_line(err.msg, "bad.csv");
        int ok = rc == -1 && line == cases[i].line && strstr(err.msg, cases[i].needle) != NULL &&
                 tr.count == 0 && tr.time_s == NULL;
        CHECK(ok);
        if (!ok)
            fprintf(stderr, "case %zu: rc %d, message \"%s\", wanted line %ld and \"%s\"\n", i, rc, err.msg,
                    cases[i].line, cases[i].needle);
    }

    /* An embedded NUL byte in a row. */
    static const char with_nul[] = "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1,0\0,0,0\n";
    struct rpl_trace tr;
    struct hl_error err = {{0}};
    CHECK(parse_exact(with_nul, sizeof with_nul - 1, "nul.csv", &tr, &err) == -1);
    CHECK(message_line(err.msg, "nul.csv") == 3 && strstr(err.msg, "NUL"));

    /* A very long line. */
    struct text big = {0};
    text_add(&big, "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.1,1");
    for (int i = 0; i < 20000; ++i)
        text_add(&big, "0000000000");
    text_add(&big, ",0,0,0\n");
    CHECK(parse_exact(big.s, big.n, "long.csv", &tr, &err) == -1);
    CHECK(message_line(err.msg, "long.csv") == 3);
    free(big.s);

    /* Renormalised within tolerance. */
    static const char near_unit[] = "t_s,qw,qx,qy,qz\n0,1.0005,0,0,0\n";
    CHECK(parse_exact(near_unit, strlen(near_unit), "n.csv", &tr, &err) == 0);
    if (tr.count == 1)
        CHECK_NEAR(tr.orientation[0].w, 1.0, 1e-15);
    rpl_trace_free(&tr);

    /* Byte mutations of the small CSV: never a crash; failures always carry a line. */
    uint64_t rng = 0x9e3779b97f4a7c15ull;
    size_t n = strlen(SMALL_CSV);
    char *buf = malloc(n);
    int mutated_fail = 0, mutated_bad = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        memcpy(buf, SMALL_CSV, n);
        for (int k = 0; k < 1 + iter % 4; ++k) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            size_t at = (size_t)(rng >> 33) % n;
            buf[at] = (char)(rng >> 17);
        }
        int rc = parse_exact(buf, n, "m.csv", &tr, &err);
        if (rc != 0) {
            ++mutated_fail;
            if (message_line(err.msg, "m.csv") < 1)
                ++mutated_bad, fprintf(stderr, "mutation without a line: %s\n", err.msg);
        }
        rpl_trace_free(&tr);
    }
    free(buf);
    CHECK(mutated_bad == 0);
    printf("mutations: %d of 3000 rejected, all with file:line\n", mutated_fail);
}

/* ---- (c) q and −q ---------------------------------------------------------------------------- */

static void test_hemisphere(void)
{
    struct text plain = {0}, alt = {0};
    text_add(&plain, "t_s,qw,qx,qy,qz\n");
    text_add(&alt, "t_s,qw,qx,qy,qz\n");
    for (int i = 0; i < 60; ++i) {
        double t = i / 60.0;
        hl_quatd q = hl_q_mul(yaw_q(10.0 * t), hl_q_from_axis_angle(hl_v3(1, 0, 0), 0.3));
        hl_quatd a = (i % 2) ? hl_q_neg(q) : q;
        text_add(&plain, "%.17g,%.17g,%.17g,%.17g,%.17g\n", t, q.w, q.x, q.y, q.z);
        text_add(&alt, "%.17g,%.17g,%.17g,%.17g,%.17g\n", t, a.w, a.x, a.y, a.z);
    }
    struct rpl_trace tp, ta;
    struct hl_error err;
    CHECK(rpl_trace_parse(plain.s, plain.n, "plain", &tp, &err) == 0);
    CHECK(rpl_trace_parse(alt.s, alt.n, "alt", &ta, &err) == 0);
    CHECK(tp.report.sign_flips == 0);
    CHECK(ta.report.sign_flips == 59);
    double worst_q = 0, worst_w = 0, max_w = 0;
    for (int k = 0; k <= 200; ++k) {
        double t = k / 200.0;
        struct trk_pose a, b;
        rpl_trace_sample(&tp, t, &a);
        rpl_trace_sample(&ta, t, &b);
        worst_q = fmax(worst_q, hl_q_angle_rad(a.orientation, b.orientation));
        worst_w = fmax(worst_w, hl_v3_length(hl_v3_sub(a.angular_velocity_radps, b.angular_velocity_radps)));
        max_w = fmax(max_w, hl_v3_length(b.angular_velocity_radps));
    }
    CHECK(worst_q < 1e-9);
    CHECK(worst_w < 1e-6);
    CHECK(max_w * HL_DEG_PER_RAD < 10.5); /* 10 deg/s, not the 360° of a sign change */
    rpl_trace_free(&tp);
    rpl_trace_free(&ta);
    free(plain.s);
    free(alt.s);
}

/* ---- (d) angular velocity -------------------------------------------------------------------- */

/* A 100 deg/s yaw about +Y at 60 Hz, timestamps rounded to 1 ms and yaw to 0.1°, small constant
 * pitch so the body and world frames differ. Optional gap and one-sample spike. */
static void make_constant_rate(struct text *t, double rate_degps, int with_gap_and_spike)
{
    text_add(t, "t_s,qw,qx,qy,qz\n");
    double skip_from = 1.0, skip_to = 1.3; /* 300 ms gap */
    for (int i = 0; i <= 180; ++i) {
        /* Sample times jitter by ±0.4 ms and the yaw grid is offset by 0.037°, so the ms and 0.1°
         * roundings do not cancel each other (at exactly 100 deg/s they otherwise would). */
        double tau = i / 60.0 + 0.0004 * sin(1.7 * i);
        if (with_gap_and_spike && tau > skip_from && tau < skip_to)
            continue;
        double t_ms = round(tau * 1000.0);
        double yaw_deg = round((rate_degps * tau + 0.037) * 10.0) / 10.0 - 0.037;
        if (with_gap_and_spike && i == 120)
            yaw_deg += 30.0; /* one sample 30° off */
        hl_quatd q = hl_q_mul(yaw_q(yaw_deg), hl_q_from_axis_angle(hl_v3(1, 0, 0), -20.0 * HL_RAD_PER_DEG));
        text_add(t, "%.3f,%.17g,%.17g,%.17g,%.17g\n", t_ms / 1000.0, q.w, q.x, q.y, q.z);
    }
}

static void test_velocity(void)
{
    const double rate = 100.0;
    struct text txt = {0};
    make_constant_rate(&txt, rate, 0);
    struct rpl_trace tr;
    struct hl_error err;
    CHECK(rpl_trace_parse(txt.s, txt.n, "rate", &tr, &err) == 0);
    double worst_rel = 0, worst_off_axis = 0;
    for (double t = 0.1; t <= 2.9; t += 0.0011) {
        struct trk_pose p;
        rpl_trace_sample(&tr, t, &p);
        hl_vec3d w = hl_v3_scale(p.angular_velocity_radps, HL_DEG_PER_RAD);
        worst_rel = fmax(worst_rel, fabs(w.y - rate) / rate); /* +Y world, positive */
        worst_off_axis = fmax(worst_off_axis, hypot(w.x, w.z));
    }
    printf("constant 100 deg/s: worst |ω_y| error %.2f %%, off-axis %.3f deg/s\n", 100 * worst_rel, worst_off_axis);
    CHECK(worst_rel < 0.03);
    CHECK(worst_off_axis < 0.03 * rate);
    rpl_trace_free(&tr);
    free(txt.s);

    struct text g = {0};
    make_constant_rate(&g, rate, 1);
    CHECK(rpl_trace_parse(g.s, g.n, "gap", &tr, &err) == 0);
    CHECK(tr.report.gaps == 1);
    CHECK(tr.report.longest_gap_s > 0.29 && tr.report.longest_gap_s < 0.32);
    CHECK(tr.report.speed_outliers == 1);
    CHECK(tr.report.max_step_speed_degps > RPL_TRACE_OUTLIER_DEGPS);
    double worst = 0;
    for (double t = 0.0; t <= 3.0; t += 0.0007) {
        struct trk_pose p;
        rpl_trace_sample(&tr, t, &p);
        worst = fmax(worst, hl_v3_length(p.angular_velocity_radps) * HL_DEG_PER_RAD);
        /* The spike is skipped for orientation too: never 30° off the ramp. */
        hl_quatd truth = hl_q_mul(yaw_q(rate * fmin(fmax(t, 0.0), 3.0)),
                                  hl_q_from_axis_angle(hl_v3(1, 0, 0), -20.0 * HL_RAD_PER_DEG));
        if (hl_q_angle_rad(p.orientation, truth) * HL_DEG_PER_RAD > 1.0) {
            CHECK(0);
            fprintf(stderr, "t=%.4f orientation off by %.2f deg\n", t, hl_q_angle_rad(p.orientation, truth) * HL_DEG_PER_RAD);
            break;
        }
    }
    printf("gap + spike: max |ω| %.1f deg/s (true %.0f)\n", worst, rate);
    CHECK(worst < 2.0 * rate);
    rpl_trace_free(&tr);
    free(g.s);
}

/* ---- (e) the Corbillon traces ---------------------------------------------------------------- */

static void corbillon_figures(const char *file, struct rpl_trace *tr, double *p50, double *p99, double *max,
                              double *up_median_deg)
{
    double t0 = tr->time_s[0], t1 = tr->time_s[tr->count - 1];
    size_t n = (size_t)((t1 - t0) * 90.0) + 1;
    double *w = malloc(n * sizeof *w);
    size_t finite = 0;
    for (size_t i = 0; i < n; ++i) {
        struct trk_pose p;
        rpl_trace_sample(tr, t0 + (double)i / 90.0, &p);
        w[i] = hl_v3_length(p.angular_velocity_radps) * HL_DEG_PER_RAD;
        finite += isfinite(w[i]) ? 1 : 0;
    }
    CHECK(finite == n);
    qsort(w, n, sizeof *w, cmp_double);
    *p50 = w[n / 2];
    *p99 = w[(size_t)(0.99 * (double)(n - 1))];
    *max = w[n - 1];
    free(w);

    double *up = malloc(tr->count * sizeof *up);
    for (size_t i = 0; i < tr->count; ++i)
        up[i] = hl_v3_angle_rad(hl_q_rotate(tr->orientation[i], hl_v3(0, 1, 0)), hl_v3(0, 1, 0)) * HL_DEG_PER_RAD;
    qsort(up, tr->count, sizeof *up, cmp_double);
    *up_median_deg = up[tr->count / 2];
    free(up);
    /* Single-sample jumps over 5° (user1 has several of 7–13° around 266–270 s): counted and shown,
     * whether or not they pass the outlier speed. */
    size_t jumps = 0, jumps_266_270 = 0;
    double jump_max_deg = 0;
    for (size_t i = 1; i < tr->count; ++i) {
        double step_deg = hl_q_angle_rad(tr->orientation[i - 1], tr->orientation[i]) * HL_DEG_PER_RAD;
        if (step_deg > 5.0 && tr->time_s[i] - tr->time_s[i - 1] <= 0.05) { /* not across a gap */
            ++jumps;
            jump_max_deg = fmax(jump_max_deg, step_deg);
            jumps_266_270 += tr->time_s[i] >= 266.0 && tr->time_s[i] <= 270.0;
        }
    }
    printf("%s: %zu single-sample jumps over 5 deg within 50 ms (largest %.1f deg), %zu of them in 266-270 s\n",
           file, jumps, jump_max_deg, jumps_266_270);
    const struct rpl_trace_report *r = &tr->report;
    printf("%s: rows %zu, flips %zu, repeats %zu, gaps>100ms %zu (longest %.0f ms), outliers %zu, "
           "max step %.1f deg/s, |ω|@90Hz p50 %.1f p99 %.1f max %.1f deg/s, up-axis median %.1f deg\n",
           file, r->rows, r->sign_flips, r->repeated_samples, r->gaps, 1000 * r->longest_gap_s, r->speed_outliers,
           r->max_step_speed_degps, *p50, *p99, *max, *up_median_deg);
}

static void test_corbillon(void)
{
    static const char *const files[] = {"user1_quaternion.txt", "user2_quaternion.txt", "user3_quaternion.txt"};
    for (int f = 0; f < 3; ++f) {
        char rel[128];
        snprintf(rel, sizeof rel, "data/traces/corbillon-mmsys18/%s", files[f]);
        const char *path = tu_shared_path(rel);
        if (!path)
            continue; /* tu_shared_path printed the skip */
        struct rpl_trace tr;
        struct hl_error err = {{0}};
        int rc = rpl_trace_load(path, &tr, &err);
        CHECK(rc == 0);
        if (rc != 0) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        CHECK(tr.format == RPL_TRACE_CORBILLON);
        double p50, p99, max, up_deg;
        corbillon_figures(files[f], &tr, &p50, &p99, &max, &up_deg);
        CHECK(max < 2000.0);
        CHECK(up_deg < 10.0); /* the frame conversion puts the head upright */
        if (f == 0) {
            /* Measured figures in the shared data README §1: 16053 rows, 248 flips, 1168 repeats,
             * 3 gaps over 100 ms. Flips count the file's own hemisphere changes, so they match
             * exactly; the tolerance allows only for rows the README might count differently. */
            CHECK(tr.report.rows == 16053);
            CHECK(tr.report.sign_flips >= 243 && tr.report.sign_flips <= 253);
            CHECK(tr.report.repeated_samples >= 1160 && tr.report.repeated_samples <= 1176);
            CHECK(tr.report.gaps >= 3);
            CHECK(p99 < 300.0);
        }
        rpl_trace_free(&tr);
    }
}

/* ---- (f) built-in clip and the pose source --------------------------------------------------- */

static void test_clip_and_source(void)
{
    struct rpl_trace tr;
    struct hl_error err;
    CHECK(rpl_trace_builtin_clip(&tr, &err) == 0);
    CHECK(tr.count == 481);
    CHECK_NEAR(tr.time_s[tr.count - 1], 8.0, 1e-12);
    CHECK(tr.report.speed_outliers == 0 && tr.report.gaps == 0 && tr.report.sign_flips == 0);
    double peak = 0, peak_t = 0, late_peak = 0;
    for (double t = 0; t <= 8.0; t += 0.001) {
        struct trk_pose p;
        rpl_trace_sample(&tr, t, &p);
        double w = hl_v3_length(p.angular_velocity_radps) * HL_DEG_PER_RAD;
        if (w > peak)
            peak = w, peak_t = t;
        if (t > 5.6 && w > late_peak)
            late_peak = w;
    }
    printf("builtin clip: peak |ω| %.1f deg/s at %.3f s, turn back peak %.1f deg/s, repeats %zu\n", peak, peak_t,
           late_peak, tr.report.repeated_samples);
    CHECK_NEAR(peak, 270.0, 27.0);
    CHECK(peak_t > 4.0 && peak_t < 4.7);
    CHECK_NEAR(late_peak, 120.0, 12.0);
    struct trk_pose still;
    rpl_trace_sample(&tr, 0.5, &still);
    CHECK(hl_v3_length(still.angular_velocity_radps) < 1e-9);

    struct trk_pose_source *src = NULL;
    CHECK(rpl_trace_source_create(&tr, &src, &err) == 0);
    CHECK(tr.count == 0 && tr.time_s == NULL); /* ownership moved */
    if (src) {
        CHECK(src->start(src, &err) == 0);
        CHECK_NEAR(src->start_time_s, 0.0, 0);
        CHECK_NEAR(src->end_time_s, 8.0, 1e-12);
        struct trk_pose p;
        CHECK(trk_source_pose_at(src, 4.3125, &p, &err) == 0);
        CHECK(hl_v3_length(p.angular_velocity_radps) * HL_DEG_PER_RAD > 200.0);
        CHECK(trk_source_pose_at(src, NAN, &p, &err) == -1);
        char reason[64];
        CHECK(src->health(src, reason, sizeof reason) == TRK_HEALTH_OK);
        src->stop(src);
        trk_source_destroy(src);
    }
    struct rpl_trace empty = {0};
    CHECK(rpl_trace_source_create(&empty, &src, &err) == -1 && src == NULL);

    /* Sampling an empty trace gives the still pose, without touching memory. */
    struct trk_pose p;
    rpl_trace_sample(&empty, 1.0, &p);
    CHECK(p.orientation.w == 1.0 && p.gaze_dir_head.z == -1.0);
}

/* The documented example file loads, and a missing file names its path. */
static void test_load(void)
{
    struct rpl_trace tr;
    struct hl_error err = {{0}};
    CHECK(rpl_trace_load("/nonexistent/trace.csv", &tr, &err) == -1);
    CHECK(strstr(err.msg, "/nonexistent/trace.csv: cannot open") == err.msg);
    const char *src = getenv("HMDLOD_SOURCE");
    if (!src || !*src) {
        printf("skip: HMDLOD_SOURCE unset, example trace not loaded\n");
        return;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/tests/data/trace_example.csv", src);
    int rc = rpl_trace_load(path, &tr, &err);
    CHECK(rc == 0);
    if (rc != 0) {
        fprintf(stderr, "%s\n", err.msg);
        return;
    }
    CHECK(tr.count == 4 && tr.position_m && tr.gaze_dir);
    struct trk_pose p;
    rpl_trace_sample(&tr, 0.015, &p);
    CHECK_NEAR(p.angular_velocity_radps.y * HL_DEG_PER_RAD, 100.0, 1e-6);
    CHECK_NEAR(p.position_m.y, 1.6, 1e-12);
    rpl_trace_free(&tr);
}

/* Nasrabadi MMSys'19 (headerless, Unity x y z w, left-handed): loads as its own format, the head is
 * upright after the mirror, and the forward axis matches the file's own view vector (data README
 * §2: the vector is q_unity·(0,0,1) with y negated, so in the project frame forward = (vx, −vy, −vz)). */
static void test_nasrabadi(void)
{
    static const char *const files[] = {"322SAJ_9.csv", "6Q9DTK_9.csv", "ANPIUN_9.csv"};
    static const size_t rows[] = {3589, 3591, 3590};
    for (int f = 0; f < 3; ++f) {
        char rel[128];
        snprintf(rel, sizeof rel, "data/traces/nasrabadi-mmsys19/%s", files[f]);
        const char *path = tu_shared_path(rel);
        if (!path)
            continue;
        char path_copy[4096];
        snprintf(path_copy, sizeof path_copy, "%s", path);
        struct rpl_trace tr;
        struct hl_error err = {{0}};
        CHECK(rpl_trace_load(path_copy, &tr, &err) == 0);
        if (tr.count == 0) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        CHECK(tr.format == RPL_TRACE_NASRABADI);
        CHECK(tr.report.rows == rows[f] && tr.count == rows[f]);
        CHECK(tr.report.sign_flips == 0 && tr.report.repeated_samples == 0);
        size_t size = 0;
        char *text = tu_read_file(path_copy, &size);
        double *fwd_err = malloc(tr.count * sizeof *fwd_err), *up = malloc(tr.count * sizeof *up);
        size_t n = 0;
        for (char *line = text; line && *line && n < tr.count; ++n) {
            double t, qx, qy, qz, qw, vx, vy, vz;
            if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &qx, &qy, &qz, &qw, &vx, &vy, &vz) != 8)
                break;
            hl_vec3d fwd = hl_q_rotate(tr.orientation[n], hl_v3(0, 0, -1));
            fwd_err[n] = hl_v3_angle_rad(fwd, hl_v3(vx, -vy, -vz)) * HL_DEG_PER_RAD;
            up[n] = hl_v3_angle_rad(hl_q_rotate(tr.orientation[n], hl_v3(0, 1, 0)), hl_v3(0, 1, 0)) * HL_DEG_PER_RAD;
            line = strchr(line, '\n');
            line = line ? line + 1 : NULL;
        }
        CHECK(n == tr.count);
        qsort(fwd_err, n, sizeof *fwd_err, cmp_double);
        qsort(up, n, sizeof *up, cmp_double);
        printf("%s: rows %zu, forward vs the file's view vector median %.3f deg, max %.3f deg; up-axis median %.1f deg\n",
               files[f], tr.count, fwd_err[n / 2], fwd_err[n - 1], up[n / 2]);
        CHECK(fwd_err[n / 2] < 0.05); /* the README measures < 0.01° median, 0.38° max */
        CHECK(fwd_err[n - 1] < 1.0);
        CHECK(up[n / 2] < 25.0); /* pitch tilts the up axis too: 6Q9DTK looks down more (17°) */
        free(fwd_err);
        free(up);
        free(text);
        rpl_trace_free(&tr);
    }
    /* Detection is strict: a headerless first line needs exactly eight numbers. */
    static const char seven[] = "0,0,0,0,1,0,0\n";
    struct rpl_trace tr;
    struct hl_error err = {{0}};
    CHECK(rpl_trace_parse(seven, sizeof seven - 1, "seven", &tr, &err) != 0 && strstr(err.msg, "seven:1:"));
    static const char two[] = "0,0,0,0,1,0,0,1\n0.02,0,0,0,1,0,0,1\n";
    CHECK(rpl_trace_parse(two, sizeof two - 1, "two", &tr, &err) == 0 && tr.count == 2);
    rpl_trace_free(&tr);
}

int main(void)
{
    test_load();
    test_small_csv();
    test_malformed();
    test_hemisphere();
    test_velocity();
    test_corbillon();
    test_nasrabadi();
    test_clip_and_source();
    return tu_finish("test_trace");
}
