/* hmdlod base: the few things every module needs — errors, a monotonic clock, bounded reading of
 * input files, double-precision vectors and quaternions, checked time arithmetic, and a terminal
 * progress bar. Prefix hl_. Nothing else belongs here. */
#ifndef HMDLOD_BASE_H
#define HMDLOD_BASE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* ---- errors ----------------------------------------------------------------------------------
 * Fallible functions return 0 on success or a negative code, and fill a struct hl_error with
 * "place: what was wrong" (place = file:line or file: field). One message, no stack of them. */
struct hl_error {
    char msg[512];
};

/* Formats the message into err (may be NULL) and returns -1, so callers can `return hl_fail(...)`. */
int hl_fail(struct hl_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* ---- clock ----------------------------------------------------------------------------------- */
int64_t hl_clock_now_ns(void); /* CLOCK_MONOTONIC, nanoseconds */
double hl_clock_now_s(void);   /* the same in seconds (double keeps ns resolution for ~100 days) */

/* ---- input files -----------------------------------------------------------------------------
 * Every loader opens its input here. Only regular files are read: a FIFO, a device (/dev/zero) or a
 * directory is refused before it can block or grow memory ("path: not a regular file (a FIFO)").
 * Whole-file reads have a size limit; the default is 1 GiB, raised (or lowered) by the environment
 * variable HMDLOD_MAX_INPUT_BYTES (a positive byte count; anything else keeps the default). */
#define HL_FILE_DEFAULT_MAX_BYTES ((uint64_t)1 << 30)
#define HL_FILE_MAX_BYTES_ENV "HMDLOD_MAX_INPUT_BYTES"
uint64_t hl_file_max_bytes(void); /* the default limit, after the environment variable */
/* Opens a regular file for reading (never blocks in open); its size in *size_out (may be NULL).
 * On failure errno says why: ENOENT for a missing file, EINVAL for one that is not regular. */
FILE *hl_file_open_read(const char *path, uint64_t *size_out, struct hl_error *err);
/* Reads the whole file into a NUL-terminated malloc'd buffer of *len_out bytes (len_out may be NULL).
 * max_bytes 0 means hl_file_max_bytes(); a larger file is an error naming the limit. */
int hl_file_read_all(const char *path, uint64_t max_bytes, char **buf_out, size_t *len_out, struct hl_error *err);

/* ---- allocation in libraries ------------------------------------------------------------------
 * For a library that reports a failed allocation as something else (cJSON: "not valid JSON"): its
 * allocator hooks, which count failures, so the caller compares the count before and after a call
 * and says "out of memory" instead. Plain malloc and free otherwise. */
void *hl_lib_malloc(size_t n);
void hl_lib_free(void *p);
uint64_t hl_lib_alloc_failures(void);

/* ---- output files ----------------------------------------------------------------------------
 * Every output file of the project is written here, so that none is ever seen half-written, none
 * follows a symlink planted in an output folder, and a full disk is an error naming the file:
 *
 *     struct hl_out o;
 *     if (hl_out_open(&o, "run/summary.json", &err) != 0) return -1;
 *     fputs(text, o.f);                         // or write(o.fd, ...) for unbuffered records
 *     if (hl_out_commit(&o, &err) != 0) return -1;   // or hl_out_abort(&o) to give up
 *
 * hl_out_open creates a fresh temporary file beside path (same folder, so the final rename is atomic)
 * with O_CREAT|O_EXCL|O_NOFOLLOW, mode 0644 less the umask: nothing that already exists there, link or
 * not, is ever opened. hl_out_commit flushes, checks every write and the close, fsyncs the data and
 * renames the temporary over path; rename replaces a symlink at path instead of following it, and a
 * previous file at path stays whole until then. Any failure unlinks the temporary and leaves path as it
 * was ("path: write failed: No space left on device"). hl_out_abort unlinks it too. Both free o.
 *
 * Streams written over a long time (a live session's --record and --log) mark each complete record
 * with hl_out_mark, which flushes it: on a failed write the stream stops, and hl_out_commit_prefix
 * cuts the file back to its last marked record and renames that valid prefix into place. The caller
 * then says the file is incomplete (docs/HARD_CASES.md, "Faults"). */
struct hl_out {
    FILE *f;           /* the temporary file, to write to (NULL once committed or aborted) */
    int fd;            /* its descriptor (for write(); do not mix with unflushed stdio output) */
    char *path;        /* the final name */
    char *tmp;         /* the temporary's name */
    uint64_t marked;   /* bytes up to the last hl_out_mark: complete records */
    uint64_t records;  /* hl_out_mark calls */
    int published;     /* hl_out_publish done: path already names the file */
    int closed;        /* hl_out_close done: written, synced and closed, not yet renamed */
    void *state_;      /* private */
};
int hl_out_open(struct hl_out *o, const char *path, struct hl_error *err);
int hl_out_commit(struct hl_out *o, struct hl_error *err);
void hl_out_abort(struct hl_out *o);
/* Everything hl_out_commit does but the rename: for outputs that belong together (frames.csv and
 * summary.json), each closed first, then all renamed, so a full disk never leaves a new one beside an
 * old one. hl_out_commit then only renames; hl_out_abort still unlinks. */
int hl_out_close(struct hl_out *o, struct hl_error *err);
/* The end of one complete record: flushes it; -1 with err (naming path and why) on a failed write. */
int hl_out_mark(struct hl_out *o, struct hl_error *err);
/* After a failed write: keeps the first o->marked bytes (o->records complete records) under path. */
int hl_out_commit_prefix(struct hl_out *o, struct hl_error *err);
/* Renames the temporary into place now and keeps writing to it (an append-only recording that must be
 * found under its name even if the process dies): after this, commit only syncs and closes, and abort
 * leaves the file. */
int hl_out_publish(struct hl_out *o, struct hl_error *err);
/* The whole of data[0..size) as path, through the steps above. */
int hl_out_write_all(const char *path, const void *data, size_t size, struct hl_error *err);
/* Makes a folder the program creates inside an output folder (DIR/runs, DIR/runs/ID, DIR/plots): mkdir,
 * then checked without following links; a symlink (or anything not a folder) there is refused. */
int hl_dir_make(const char *path, struct hl_error *err);

/* ---- checked time and counter arithmetic ------------------------------------------------------
 * Timestamps, tick counters and counts come from files and devices, so any value is possible. Each
 * function returns 0 with the exact result in *out, or -1 (leaving *out untouched) when the result
 * does not fit: the caller turns -1 into an error naming the file and record, never a wrapped value. */
static inline int hl_i64_add_checked(int64_t a, int64_t b, int64_t *out)
{
    int64_t r;
    if (__builtin_add_overflow(a, b, &r))
        return -1;
    *out = r;
    return 0;
}
static inline int hl_i64_sub_checked(int64_t a, int64_t b, int64_t *out)
{
    int64_t r;
    if (__builtin_sub_overflow(a, b, &r))
        return -1;
    *out = r;
    return 0;
}
static inline int hl_i64_mul_checked(int64_t a, int64_t b, int64_t *out)
{
    int64_t r;
    if (__builtin_mul_overflow(a, b, &r))
        return -1;
    *out = r;
    return 0;
}
static inline int hl_size_mul_checked(size_t a, size_t b, size_t *out)
{
    size_t r;
    if (__builtin_mul_overflow(a, b, &r))
        return -1;
    *out = r;
    return 0;
}
/* x truncated toward zero; -1 for NaN, ±inf, or a value outside [-2^63, 2^63). */
int hl_i64_from_double(double x, int64_t *out);
/* x truncated toward zero, clamped to [INT64_MIN, INT64_MAX]; NaN gives 0. For limits where
 * "infinitely long" is a legitimate request (a time limit of +inf means none). */
int64_t hl_i64_from_double_saturating(double x);
/* Seconds to integer nanoseconds, rounded to nearest; -1 when not finite or beyond ±292 years. */
int hl_ns_from_s(double seconds, int64_t *ns_out);

/* ---- vectors (double; world positions and fusion state) --------------------------------------- */
typedef struct hl_vec3d {
    double x, y, z;
} hl_vec3d;

static inline hl_vec3d hl_v3(double x, double y, double z) { hl_vec3d v = {x, y, z}; return v; }
static inline hl_vec3d hl_v3_add(hl_vec3d a, hl_vec3d b) { return hl_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline hl_vec3d hl_v3_sub(hl_vec3d a, hl_vec3d b) { return hl_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline hl_vec3d hl_v3_scale(hl_vec3d a, double s) { return hl_v3(a.x * s, a.y * s, a.z * s); }
static inline double hl_v3_dot(hl_vec3d a, hl_vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline hl_vec3d hl_v3_cross(hl_vec3d a, hl_vec3d b)
{
    return hl_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
double hl_v3_length(hl_vec3d a);              /* ≤ 3 ulp from hypot; no overflow for 1e200-sized inputs */
hl_vec3d hl_v3_normalize(hl_vec3d a);         /* zero vector stays zero */
double hl_v3_angle_rad(hl_vec3d a, hl_vec3d b); /* atan2(|a×b|, a·b): exact near 0 and π; 0 if either is zero */

/* ---- quaternions, scalar first (w x y z) — the order of trace files. cglm's versor is x y z w. -- */
typedef struct hl_quatd {
    double w, x, y, z;
} hl_quatd;

static inline hl_quatd hl_q(double w, double x, double y, double z) { hl_quatd q = {w, x, y, z}; return q; }
static inline hl_quatd hl_q_identity(void) { return hl_q(1, 0, 0, 0); }
static inline double hl_q_dot(hl_quatd a, hl_quatd b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; }
static inline hl_quatd hl_q_conj(hl_quatd q) { return hl_q(q.w, -q.x, -q.y, -q.z); }
static inline hl_quatd hl_q_neg(hl_quatd q) { return hl_q(-q.w, -q.x, -q.y, -q.z); }
hl_quatd hl_q_mul(hl_quatd a, hl_quatd b);      /* Hamilton product a ⊗ b */
double hl_q_norm(hl_quatd q);
hl_quatd hl_q_normalize(hl_quatd q);            /* zero quaternion → identity */
hl_vec3d hl_q_rotate(hl_quatd q, hl_vec3d v);   /* q v q*, q unit */
hl_quatd hl_q_from_axis_angle(hl_vec3d axis, double angle_rad);
hl_quatd hl_q_exp(hl_vec3d rotvec_rad);         /* rotation vector → unit quaternion (stable near 0) */
hl_vec3d hl_q_log(hl_quatd q);                  /* unit quaternion → rotation vector, shortest arc, atan2-based */
double hl_q_angle_rad(hl_quatd a, hl_quatd b);  /* rotation angle between two orientations, in [0, π] */
hl_quatd hl_q_slerp(hl_quatd a, hl_quatd b, double t); /* shortest arc; b flipped when a·b < 0 */

/* ---- samples -------------------------------------------------------------------------------------
 * Sorting and nearest-rank percentiles of measured doubles (frame times, errors), shared so that every
 * median and p99 in the project means the same thing. NaN must be kept out by the caller. */
void hl_sort_doubles(double *v, size_t n);                               /* ascending, in place */
double hl_percentile_sorted(const double *sorted, size_t n, double p);  /* nearest rank: the smallest value
                                                                          * with at least p·n at or below it;
                                                                          * 0 for n = 0 */

/* ---- little-endian fields (bytes.c) ------------------------------------------------------------
 * The binary formats' fields (.lod, tracker recordings, .glb headers), read and written byte by byte:
 * any host byte order, any alignment of p. Floats are their IEEE 754 bits. */
void hl_le_put_u16(unsigned char *p, uint16_t v);
void hl_le_put_u32(unsigned char *p, uint32_t v);
void hl_le_put_u64(unsigned char *p, uint64_t v);
void hl_le_put_f32(unsigned char *p, float f);
void hl_le_put_f64(unsigned char *p, double d);
uint16_t hl_le_get_u16(const unsigned char *p);
uint32_t hl_le_get_u32(const unsigned char *p);
uint64_t hl_le_get_u64(const unsigned char *p);
float hl_le_get_f32(const unsigned char *p);
double hl_le_get_f64(const unsigned char *p);

#define HL_PI 3.14159265358979323846
#define HL_DEG_PER_RAD (180.0 / HL_PI)
#define HL_RAD_PER_DEG (HL_PI / 180.0)

/* ---- progress bar ----------------------------------------------------------------------------
 * Draws "label [#####.....] 42% 12/30" on stderr when stderr is a terminal; silent otherwise. */
struct hl_progress {
    const char *label;
    uint64_t total;
    int enabled;
    int last_permille;
};
void hl_progress_begin(struct hl_progress *p, const char *label, uint64_t total);
void hl_progress_update(struct hl_progress *p, uint64_t done);
void hl_progress_end(struct hl_progress *p);

#endif
