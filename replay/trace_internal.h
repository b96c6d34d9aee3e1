/* Internal to replay/: the row-by-row builder that the parsers, the raw-recording reader and the
 * built-in clip share, so every trace gets exactly the same hemisphere, repeated-timestamp, repeat,
 * gap and outlier handling as a file; and the few text helpers the two row readers share. */
#ifndef HMDLOD_REPLAY_TRACE_INTERNAL_H
#define HMDLOD_REPLAY_TRACE_INTERNAL_H

#include "replay/replay.h"

/* After this many consecutive speed outliers the next sample is accepted as the new reference:
 * a longer excursion is a real re-orientation (tracking re-acquired), not a glitch. It also bounds
 * the walk past outliers in rpl_trace_sample, which keeps sampling O(log n). */
#define RPL_TRACE_MAX_OUTLIER_RUN 3

struct trace_builder {
    struct rpl_trace *trace;   /* arrays allocated with `capacity` entries */
    size_t capacity;
    hl_quatd prev_raw;         /* previous row's quaternion as read (before any flip) */
    int prev_flipped;          /* whether the previous row was stored negated */
};

/* Allocates arrays for `capacity` rows (position/gaze only when asked). 0 or −1 with err. */
int trace_builder_init(struct trace_builder *b, struct rpl_trace *out, enum rpl_trace_format format,
                       size_t capacity, int has_position, int has_gaze, struct hl_error *err);

/* Appends one validated row: time at or after the previous row's (equal times are resolved by
 * trace_builder_finish), q unit (project frame, as read, any hemisphere), gaze unit when present.
 * Keeps q in the previous row's hemisphere. The caller guarantees count < capacity. */
void trace_builder_push(struct trace_builder *b, double time_s, hl_quatd q_unit, const hl_vec3d *position_m,
                        const hl_vec3d *gaze_unit);

/* After the last push: spreads rows that share a timestamp (docs/trace-format.md §3), then fills the
 * gap, step-speed and outlier parts of the report. Fails only when several rows exist and all share
 * one time (no rate to spread them over): "name:first_row_line: …"; the trace is then freed. */
int trace_builder_finish(struct trace_builder *b, const char *name, size_t first_row_line, struct hl_error *err);

/* ---- text helpers shared by trace_parse.c and trace_edvam.c ---------------------------------- */

/* Trims spaces, tabs and a CR (CRLF files) from both ends of [*s, *s+*n). */
void trace_trim(const char **s, size_t *n);
/* Lines with content (not blank, not a comment), at least 1: the most rows a text can hold. Arrays
 * are sized from this, so blank-line padding costs no memory. */
size_t trace_count_content_lines(const char *text, size_t length);

/* Copies a field for a message (at most size − 1 bytes), replacing anything unprintable. */
void trace_quote_field(const char *s, size_t n, char *buf, size_t size);

/* Reads one field [s, s+n) (trimmed here) as a finite double. Returns 0, or −1 with
 * "name:line: column COLUMN: empty field | not a number: "…" | not finite: "…"". */
int trace_read_number(const char *name, size_t line_no, const char *column, const char *s, size_t n, double *x,
                      struct hl_error *err);

/* The EDVAM eye-tracker log (trace_edvam.c): detection by the header's first fields, and the whole
 * parse (the text from its start; same contract as rpl_trace_parse). */
int trace_is_edvam_header(const char *s, size_t n);
int trace_parse_edvam(const char *text, size_t length, const char *name, struct rpl_trace *out,
                      struct hl_error *err);

#endif
