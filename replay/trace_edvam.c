/* The EDVAM eye-tracker log (Zhou et al. 2022; shared data README §3), read as it is: 44 comma
 * separated columns, CRLF, `index,time` named twice, camera position C and forward F rounded to 0.1,
 * the 3D point of gaze L, the Pupil confidence. Its own row reader: rows are ~450 bytes and only
 * the first 12 columns (and the repeated index,time) are read. Rules in docs/trace-format.md §2c. */
#include "replay/trace_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EDVAM_MAX_COLUMNS 64
#define EDVAM_LINE_MAX_BYTES 4096 /* the real rows are ≤ 431 bytes, the header ~700 */
#define EDVAM_NAME_BYTES 32
#define EDVAM_MIN_FORWARD 0.8 /* |F| bounds: 0.1 rounding of a unit vector gives 0.91–1.09 */
#define EDVAM_MAX_FORWARD 1.2
#define EDVAM_MIN_GAZE_DISTANCE_M 1e-6 /* L = C: no gaze ray */

static const char EDVAM_PREFIX[] = "index,time,L_x,L_y,L_z,C_x,C_y,C_z,F_x,F_y,F_z,confidence";
enum { COL_INDEX = 0, COL_TIME = 1, COL_L = 2, COL_C = 5, COL_F = 8, COL_CONF = 11, COLS_USED = 12 };

struct edvam_header {
    int columns;
    char names[EDVAM_MAX_COLUMNS][EDVAM_NAME_BYTES];
    int dup_index, dup_time; /* the later `index` / `time` columns, −1 when absent */
};

/* One row's values in Unity's frame, as read. */
struct edvam_row {
    double v[COLS_USED];
};

int trace_is_edvam_header(const char *s, size_t n)
{
    size_t k = sizeof EDVAM_PREFIX - 1;
    return n >= k && memcmp(s, EDVAM_PREFIX, k) == 0 && (n == k || s[k] == ',');
}

/* Splits [s, s+n) at commas; fills at most EDVAM_MAX_COLUMNS spans, returns the field count. */
static int split_fields(const char *s, size_t n, const char **fs, size_t *fn)
{
    int count = 0;
    size_t i = 0;
    for (;;) {
        size_t start = i;
        while (i < n && s[i] != ',')
            ++i;
        if (count < EDVAM_MAX_COLUMNS) {
            fs[count] = s + start;
            fn[count] = i - start;
        }
        ++count;
        if (i >= n)
            return count;
        ++i;
    }
}

static int read_header(const char *name, size_t line_no, const char *s, size_t n, struct edvam_header *H,
                       struct hl_error *err)
{
    const char *fs[EDVAM_MAX_COLUMNS];
    size_t fn[EDVAM_MAX_COLUMNS];
    int count = split_fields(s, n, fs, fn);
    if (count > EDVAM_MAX_COLUMNS)
        return hl_fail(err, "%s:%zu: EDVAM header has %d columns, at most %d", name, line_no, count, EDVAM_MAX_COLUMNS);
    H->columns = count;
    H->dup_index = H->dup_time = -1;
    for (int c = 0; c < count; ++c) {
        const char *f = fs[c];
        size_t m = fn[c];
        trace_trim(&f, &m);
        trace_quote_field(f, m, H->names[c], sizeof H->names[c]);
        if (c >= COLS_USED && H->dup_index < 0 && m == 5 && memcmp(f, "index", 5) == 0)
            H->dup_index = c;
        if (c >= COLS_USED && H->dup_time < 0 && m == 4 && memcmp(f, "time", 4) == 0)
            H->dup_time = c;
    }
    return 0;
}

/* A repeated index/time column must equal the first: a difference means rows were spliced. */
static int check_duplicate(const char *name, size_t line_no, const struct edvam_header *H, int col, int first,
                           double first_value, const char **fs, const size_t *fn, struct hl_error *err)
{
    if (col < 0)
        return 0;
    double x;
    char column[EDVAM_NAME_BYTES + 24];
    snprintf(column, sizeof column, "%s (field %d)", H->names[col], col + 1);
    if (trace_read_number(name, line_no, column, fs[col], fn[col], &x, err) != 0)
        return -1;
    if (x != first_value)
        return hl_fail(err, "%s:%zu: column %s: %.9g differs from field %d (%.9g)", name, line_no, column, x,
                       first + 1, first_value);
    return 0;
}

/* Splits and checks one data row: column count, the used columns finite numbers, time not before
 * *prev_t (when given), the repeated columns equal, confidence in [0, 1], |F| near 1. 0 or −1 with "name:line: column NAME: reason". */
static int read_row(const char *name, size_t line_no, const struct edvam_header *H, const char *s, size_t n,
                    const double *prev_t, struct edvam_row *row, struct hl_error *err)
{
    const char *fs[EDVAM_MAX_COLUMNS];
    size_t fn[EDVAM_MAX_COLUMNS];
    int count = split_fields(s, n, fs, fn);
    if (count != H->columns)
        return hl_fail(err, "%s:%zu: expected %d columns, found %d", name, line_no, H->columns, count);
    for (int c = 0; c < COLS_USED; ++c)
        if (trace_read_number(name, line_no, H->names[c], fs[c], fn[c], &row->v[c], err) != 0)
            return -1;
    if (prev_t && row->v[COL_TIME] < *prev_t)
        return hl_fail(err, "%s:%zu: column time: time goes backwards (%.9g s after %.9g s)", name, line_no,
                       row->v[COL_TIME], *prev_t);
    if (check_duplicate(name, line_no, H, H->dup_index, COL_INDEX, row->v[COL_INDEX], fs, fn, err) != 0 ||
        check_duplicate(name, line_no, H, H->dup_time, COL_TIME, row->v[COL_TIME], fs, fn, err) != 0)
        return -1;
    double conf = row->v[COL_CONF];
    if (conf < 0.0 || conf > 1.0)
        return hl_fail(err, "%s:%zu: column confidence: %.9g is outside [0, 1]", name, line_no, conf);
    double f_len = hypot(hypot(row->v[COL_F], row->v[COL_F + 1]), row->v[COL_F + 2]);
    if (!(f_len >= EDVAM_MIN_FORWARD && f_len <= EDVAM_MAX_FORWARD))
        return hl_fail(err, "%s:%zu: columns F_x,F_y,F_z: forward vector length %.3g is not 1 (%.1f–%.1f allowed)",
                       name, line_no, f_len, EDVAM_MIN_FORWARD, EDVAM_MAX_FORWARD);
    return 0;
}

/* Unity's left-handed frame (+X right, +Y up, +Z forward) → the project's (+Z back): mirror Z,
 * as for the Nasrabadi traces (data README §5 step 1). */
static hl_vec3d unity_point(const double *v) { return hl_v3(v[0], v[1], -v[2]); }

/* Head orientation from the forward vector alone: yaw about world +Y, then pitch about the head's
 * +X, no roll (not recorded), so the head's up stays in the vertical plane. */
static hl_quatd forward_orientation(hl_vec3d f)
{
    double yaw = atan2(-f.x, -f.z);
    double pitch = atan2(f.y, hypot(f.x, f.z));
    return hl_q_mul(hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw), hl_q_from_axis_angle(hl_v3(1, 0, 0), pitch));
}

static int is_placeholder(const struct edvam_row *r)
{
    const double *v = r->v;
    return v[COL_C] == 0 && v[COL_C + 1] == 0 && v[COL_C + 2] == 0 && v[COL_F] == 0 && v[COL_F + 1] == 0 &&
           v[COL_F + 2] == 1;
}

/* Rows without a measured gaze take the world direction interpolated (normalised lerp in time)
 * between the nearest measured rows, held before the first and after the last; then every row's
 * world gaze becomes head-frame, gaze_dir = q* g q. On entry gaze_dir holds the measured world gazes. */
static void fill_gaze(struct rpl_trace *tr, const unsigned char *measured)
{
    size_t n = tr->count, prev = n; /* n: no measured row yet */
    for (size_t i = 0; i < n; ++i) {
        if (measured[i]) {
            prev = i;
            continue;
        }
        size_t next = i + 1;
        while (next < n && !measured[next])
            ++next;
        hl_vec3d g;
        if (prev == n)
            g = tr->gaze_dir[next];
        else if (next == n)
            g = tr->gaze_dir[prev];
        else {
            hl_vec3d a = tr->gaze_dir[prev], b = tr->gaze_dir[next];
            double u = (tr->time_s[i] - tr->time_s[prev]) / (tr->time_s[next] - tr->time_s[prev]);
            g = hl_v3_add(a, hl_v3_scale(hl_v3_sub(b, a), u));
            double len = hl_v3_length(g);
            g = len > 1e-9 ? hl_v3_scale(g, 1.0 / len) : a;
        }
        tr->gaze_dir[i] = g;
    }
    for (size_t i = 0; i < n; ++i)
        tr->gaze_dir[i] = hl_q_rotate(hl_q_conj(tr->orientation[i]), tr->gaze_dir[i]);
}

/* The state carried from row to row. */
struct edvam_state {
    int have_real;
    hl_vec3d origin_m;  /* the first real row's camera position (project frame) */
    hl_quatd prev_q;
    double prev_t;
    size_t rows_seen;   /* rows read, placeholders included (for the backwards-time check) */
    size_t first_row_line;
};

/* Turns one checked row into a trace row (or skips a leading placeholder). */
static void take_row(struct trace_builder *b, struct edvam_state *st, const struct edvam_row *r, size_t line_no,
                     unsigned char *measured)
{
    struct rpl_trace *tr = b->trace;
    if (!st->have_real && is_placeholder(r)) {
        ++tr->report.placeholder_rows;
        return;
    }
    hl_vec3d c = unity_point(r->v + COL_C);
    hl_vec3d f = hl_v3_normalize(unity_point(r->v + COL_F));
    if (!st->have_real) {
        st->have_real = 1;
        st->origin_m = c;
        st->first_row_line = line_no;
    }
    hl_quatd q;
    double from_vertical_deg = atan2(hypot(f.x, f.z), fabs(f.y)) * HL_DEG_PER_RAD;
    if (from_vertical_deg < RPL_EDVAM_VERTICAL_DEG && tr->count > 0) {
        q = st->prev_q; /* yaw is undefined there: keep the last heading */
        ++tr->report.held_orientations;
    } else {
        q = forward_orientation(f);
    }
    hl_vec3d p = hl_v3_sub(c, st->origin_m);
    hl_vec3d d = hl_v3_sub(unity_point(r->v + COL_L), c);
    double dist_m = hl_v3_length(d);
    int ok = r->v[COL_CONF] >= RPL_EDVAM_MIN_CONFIDENCE && dist_m > EDVAM_MIN_GAZE_DISTANCE_M;
    hl_vec3d g = ok ? hl_v3_scale(d, 1.0 / dist_m) : hl_v3(0, 0, -1);
    measured[tr->count] = (unsigned char)ok;
    if (!ok)
        ++tr->report.low_confidence_gaze;
    trace_builder_push(b, r->v[COL_TIME], q, &p, &g); /* world gaze for now; fill_gaze converts */
    st->prev_q = q;
}

/* Frees what the parse holds and fails: the one exit for every error after allocation. */
static int fail_free(struct rpl_trace *out, unsigned char *measured)
{
    free(measured);
    rpl_trace_free(out);
    return -1;
}

int trace_parse_edvam(const char *text, size_t length, const char *name, struct rpl_trace *out, struct hl_error *err)
{
    size_t lines = trace_count_content_lines(text, length); /* blank padding costs nothing */
    struct trace_builder b;
    if (trace_builder_init(&b, out, RPL_TRACE_EDVAM, lines, 1, 1, err) != 0)
        return -1;
    unsigned char *measured = calloc(lines, 1);
    struct edvam_header *H = malloc(sizeof *H);
    if (!measured || !H) {
        free(H);
        return fail_free(out, measured), hl_fail(err, "%s: out of memory for %zu rows", name, lines);
    }
    struct edvam_state st = {0};
    int have_header = 0;
    size_t header_line = 0, pos = 0, line_no = 0;
    int rc = 0;
    while (pos < length && rc == 0) {
        ++line_no;
        const char *line = text + pos;
        const char *nl = memchr(line, '\n', length - pos);
        size_t n = nl ? (size_t)(nl - line) : length - pos;
        pos += n + (nl ? 1 : 0);
        const char *s = line;
        size_t m = n;
        trace_trim(&s, &m);
        if (m == 0 || s[0] == '#')
            continue;
        if (memchr(s, '\0', m))
            rc = hl_fail(err, "%s:%zu: NUL byte in the line", name, line_no);
        else if (m > EDVAM_LINE_MAX_BYTES)
            rc = hl_fail(err, "%s:%zu: line too long (%zu bytes, at most %d)", name, line_no, m, EDVAM_LINE_MAX_BYTES);
        else if (!have_header) {
            rc = read_header(name, line_no, s, m, H, err);
            have_header = 1, header_line = line_no;
        } else if (!nl) {
            rc = hl_fail(err, "%s:%zu: truncated last row (no end of line)", name, line_no);
        } else {
            struct edvam_row r;
            rc = read_row(name, line_no, H, s, m, st.rows_seen > 0 ? &st.prev_t : NULL, &r, err);
            if (rc == 0) {
                take_row(&b, &st, &r, line_no, measured);
                st.prev_t = r.v[COL_TIME];
                ++st.rows_seen;
            }
        }
    }
    free(H);
    if (rc != 0)
        return fail_free(out, measured);
    if (out->count == 0) {
        fail_free(out, measured);
        return hl_fail(err, "%s:%zu: no data rows after the header%s", name, header_line,
                       st.rows_seen ? " (only placeholder rows)" : "");
    }
    /* Finish first: the gaze is interpolated on the final (spread) times. */
    if (trace_builder_finish(&b, name, st.first_row_line, err) != 0) {
        free(measured);
        return -1;
    }
    if (out->report.low_confidence_gaze == out->count) {
        free(out->gaze_dir); /* not one measured gaze: the trace has none */
        out->gaze_dir = NULL;
    } else {
        fill_gaze(out, measured);
    }
    free(measured);
    return 0;
}
