/* Trace parsing: the project's CSV, Corbillon MMSys'18 and Nasrabadi MMSys'19 text files, held in memory
 * (the EDVAM eye-tracker log is recognised here and read by trace_edvam.c). Every rule is in
 * docs/trace-format.md. The parser never reads past `length` and never relies on a NUL: each line
 * is bounded by the buffer, and only data lines' fields are copied (bounded) for strtod. */
#include "replay/trace_internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define LINE_MAX_BYTES 1024 /* a data row is at most ~11 numbers; far longer is not a trace */
#define MAX_COLUMNS 11

static const char CORBILLON_HEADER[] = "timestamp viewpoint w x y z";
static const char CSV_HEADER_BASE[] = "t_s,qw,qx,qy,qz";
static const char CSV_EXPECTED[] =
    "\"t_s,qw,qx,qy,qz[,px,py,pz][,gx,gy,gz]\", \"timestamp viewpoint w x y z\", or headerless Nasrabadi rows "
    "\"t,qx,qy,qz,qw,vx,vy,vz\"";
#define NASRABADI_COLUMNS 8

struct layout {
    enum rpl_trace_format format;
    int first_line_is_data; /* headerless format: the line that identified it is a row */
    int columns;
    int has_position, has_gaze;
    int pos_col, gaze_col; /* first column of each group */
    const char *names[MAX_COLUMNS];
};

static int is_blank(char c) { return c == ' ' || c == '\t'; }

static int span_equals(const char *s, size_t n, const char *lit)
{
    size_t m = strlen(lit);
    return n == m && memcmp(s, lit, m) == 0;
}

/* A headerless Nasrabadi row: exactly 8 comma-separated fields, each a whole number (strtod
 * consumes it all). Only the first line is tested; the rows after it are checked as data. */
static int is_nasrabadi_row(const char *s, size_t n)
{
    char buf[LINE_MAX_BYTES + 1];
    if (n > LINE_MAX_BYTES)
        return 0;
    memcpy(buf, s, n);
    buf[n] = '\0';
    int fields = 0;
    for (char *p = buf;; ++fields) {
        char *end = NULL;
        strtod(p, &end);
        if (end == p)
            return 0;
        while (is_blank(*end))
            ++end;
        if (*end == '\0')
            return fields + 1 == NASRABADI_COLUMNS;
        if (*end != ',')
            return 0;
        p = end + 1;
    }
}

/* Recognises the header (or a headerless Nasrabadi first row); 0 on success. */
static int detect_layout(const char *s, size_t n, struct layout *L)
{
    static const char *const nas_names[] = {"t", "qx", "qy", "qz", "qw", "vx", "vy", "vz"};
    static const char *const csv_names[] = {"t_s", "qw", "qx", "qy", "qz", "px", "py", "pz", "gx", "gy", "gz"};
    static const char *const corb_names[] = {"timestamp", "viewpoint", "w", "x", "y", "z"};
    memset(L, 0, sizeof *L);
    if (span_equals(s, n, CORBILLON_HEADER)) {
        L->format = RPL_TRACE_CORBILLON;
        L->columns = 6;
        for (int i = 0; i < 6; ++i)
            L->names[i] = corb_names[i];
        return 0;
    }
    if (is_nasrabadi_row(s, n)) {
        L->format = RPL_TRACE_NASRABADI;
        L->first_line_is_data = 1;
        L->columns = NASRABADI_COLUMNS;
        for (int i = 0; i < NASRABADI_COLUMNS; ++i)
            L->names[i] = nas_names[i];
        return 0;
    }
    size_t base = sizeof CSV_HEADER_BASE - 1;
    if (n < base || memcmp(s, CSV_HEADER_BASE, base) != 0)
        return -1;
    const char *rest = s + base;
    size_t rn = n - base;
    L->format = RPL_TRACE_HMDLOD_CSV;
    for (int i = 0; i < 5; ++i)
        L->names[i] = csv_names[i];
    L->columns = 5;
    if (rn >= 9 && memcmp(rest, ",px,py,pz", 9) == 0) {
        L->has_position = 1;
        L->pos_col = L->columns;
        for (int i = 0; i < 3; ++i)
            L->names[L->columns++] = csv_names[5 + i];
        rest += 9, rn -= 9;
    }
    if (rn >= 9 && memcmp(rest, ",gx,gy,gz", 9) == 0) {
        L->has_gaze = 1;
        L->gaze_col = L->columns;
        for (int i = 0; i < 3; ++i)
            L->names[L->columns++] = csv_names[8 + i];
        rest += 9, rn -= 9;
    }
    return rn == 0 ? 0 : -1;
}

/* Splits a data line (already trimmed, no NUL inside) into fields and converts each to a finite
 * double. Returns 0, or −1 with the message filled. */
static int parse_row(const char *name, size_t line_no, const char *s, size_t n, const struct layout *L,
                     double *v, struct hl_error *err)
{
    const char *fs[MAX_COLUMNS + 1];
    size_t fn[MAX_COLUMNS + 1];
    int count = 0;
    size_t i = 0;
    if (L->format != RPL_TRACE_CORBILLON) {
        for (;;) {
            size_t start = i;
            while (i < n && s[i] != ',')
                ++i;
            if (count <= MAX_COLUMNS) {
                fs[count] = s + start;
                fn[count] = i - start;
            }
            ++count;
            if (i >= n)
                break;
            ++i; /* the comma */
        }
    } else {
        while (i < n) {
            while (i < n && is_blank(s[i]))
                ++i;
            if (i >= n)
                break;
            size_t start = i;
            while (i < n && !is_blank(s[i]))
                ++i;
            if (count <= MAX_COLUMNS) {
                fs[count] = s + start;
                fn[count] = i - start;
            }
            ++count;
        }
    }
    if (count != L->columns)
        return hl_fail(err, "%s:%zu: expected %d columns, found %d", name, line_no, L->columns, count);

    for (int c = 0; c < count; ++c)
        if (trace_read_number(name, line_no, L->names[c], fs[c], fn[c], &v[c], err) != 0)
            return -1;
    return 0;
}

int rpl_trace_parse(const char *text, size_t length, const char *name, struct rpl_trace *out,
                    struct hl_error *err)
{
    if (!name)
        name = "trace";
    if (!out)
        return hl_fail(err, "%s: no output trace", name);
    memset(out, 0, sizeof *out);
    if (!text && length > 0)
        return hl_fail(err, "%s:1: no text", name);

    /* Rows ≤ lines with content: one pass sizes the arrays so the parse never reallocates, and
     * blank lines or comments (padding) cost nothing. */
    size_t lines = trace_count_content_lines(text, length);

    struct layout L;
    int have_header = 0;
    size_t header_line = 0, first_row_line = 0;
    struct trace_builder b;
    size_t pos = 0, line_no = 0;
    double prev_t = 0.0;

    while (pos < length) {
        ++line_no;
        const char *line = text + pos;
        const char *nl = memchr(line, '\n', length - pos);
        size_t n = nl ? (size_t)(nl - line) : length - pos;
        int terminated = nl != NULL;
        pos += n + (terminated ? 1 : 0);

        const char *s = line;
        size_t m = n;
        trace_trim(&s, &m);
        if (m == 0 || s[0] == '#')
            continue; /* blank or comment; content is never read further */

        if (!have_header && trace_is_edvam_header(s, m))
            return trace_parse_edvam(text, length, name, out, err); /* its own row reader, from the start */
        if (memchr(s, '\0', m))
            return rpl_trace_free(out), hl_fail(err, "%s:%zu: NUL byte in the line", name, line_no);
        if (m > LINE_MAX_BYTES)
            return rpl_trace_free(out),
                   hl_fail(err, "%s:%zu: line too long (%zu bytes, at most %d)", name, line_no, m, LINE_MAX_BYTES);

        if (!have_header) {
            if (detect_layout(s, m, &L) != 0)
                return hl_fail(err, "%s:%zu: unrecognised header (expected %s)", name, line_no, CSV_EXPECTED);
            have_header = 1;
            header_line = line_no;
            if (trace_builder_init(&b, out, L.format, lines, L.has_position, L.has_gaze, err) != 0)
                return -1;
            if (!L.first_line_is_data)
                continue;
        }

        /* A row without its end of line was cut off: its last number may be a prefix of the real
         * one, so a half row is never taken as data. */
        if (!terminated) {
            rpl_trace_free(out);
            return hl_fail(err, "%s:%zu: truncated last row (no end of line)", name, line_no);
        }

        double v[MAX_COLUMNS] = {0};
        if (parse_row(name, line_no, s, m, &L, v, err) != 0)
            return rpl_trace_free(out), -1;

        double t = v[0];
        /* w x y z from each layout: Corbillon after its viewpoint column, Nasrabadi in Unity's x y z w. */
        double wxyz[4];
        if (L.format == RPL_TRACE_NASRABADI)
            wxyz[0] = v[4], wxyz[1] = v[1], wxyz[2] = v[2], wxyz[3] = v[3];
        else
            memcpy(wxyz, L.format == RPL_TRACE_CORBILLON ? v + 2 : v + 1, sizeof wxyz);
        const double *qv = wxyz;
        /* An equal time is a coarse clock's repeat, resolved by trace_builder_finish; only a time
         * that goes backwards is an error. */
        if (out->count > 0 && t < prev_t)
            return rpl_trace_free(out),
                   hl_fail(err, "%s:%zu: time goes backwards (%.9g s after %.9g s)", name, line_no, t, prev_t);

        hl_quatd q = hl_q(qv[0], qv[1], qv[2], qv[3]);
        double norm = hl_q_norm(q);
        if (!(fabs(norm - 1.0) <= RPL_TRACE_UNIT_TOLERANCE))
            return rpl_trace_free(out),
                   hl_fail(err, "%s:%zu: quaternion norm %.9g is not 1 (tolerance %g)", name, line_no, norm,
                           RPL_TRACE_UNIT_TOLERANCE);
        q = hl_q_normalize(q);
        if (L.format == RPL_TRACE_CORBILLON)
            q = hl_q(q.w, -q.y, q.z, -q.x); /* file x fwd / y left / z up → +X right, +Y up, +Z back */
        else if (L.format == RPL_TRACE_NASRABADI)
            q = hl_q(q.w, -q.x, -q.y, q.z); /* Unity left-handed, Y up, Z fwd: mirror Z (data README §5) */

        hl_vec3d p, g;
        if (L.has_position)
            p = hl_v3(v[L.pos_col], v[L.pos_col + 1], v[L.pos_col + 2]);
        if (L.has_gaze) {
            g = hl_v3(v[L.gaze_col], v[L.gaze_col + 1], v[L.gaze_col + 2]);
            double len = hl_v3_length(g);
            if (!(len > 1e-9))
                return rpl_trace_free(out), hl_fail(err, "%s:%zu: gaze vector has zero length", name, line_no);
            g = hl_v3_scale(g, 1.0 / len);
        }
        if (out->count == 0)
            first_row_line = line_no;
        trace_builder_push(&b, t, q, L.has_position ? &p : NULL, L.has_gaze ? &g : NULL);
        prev_t = t;
    }

    if (!have_header)
        return hl_fail(err, "%s:%zu: empty input: no header (expected %s)", name, line_no + 1, CSV_EXPECTED);
    if (out->count == 0) {
        rpl_trace_free(out);
        return hl_fail(err, "%s:%zu: no data rows after the header", name, header_line);
    }
    return trace_builder_finish(&b, name, first_row_line, err);
}

int rpl_trace_load(const char *path, struct rpl_trace *out, struct hl_error *err)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!path)
        return hl_fail(err, "trace: no path");
    /* Regular files only (a FIFO or /dev/zero is refused before it can block or grow memory), at
     * most hl_file_max_bytes() (1 GiB unless HMDLOD_MAX_INPUT_BYTES says otherwise). */
    char *buf = NULL;
    size_t len = 0;
    if (hl_file_read_all(path, 0, &buf, &len, err) != 0)
        return -1;
    int rc = rpl_trace_parse(buf, len, path, out, err);
    free(buf);
    return rc;
}
