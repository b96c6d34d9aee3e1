/* A raw tracker recording as a trace: the recorded reports are fed, in file order, through the same
 * trk_stream (parser + fusion) a live session uses, and the fused orientation after each report
 * becomes one row. Replaying a recording therefore shows what the live fusion would have shown. */
#include <stdlib.h>

#include "replay/trace_internal.h"

/* Counts the complete records (and validates the whole file) before anything is allocated: the
 * trace arrays are sized from the count, never from a length read out of the file. */
static int count_records(const char *path, uint64_t *count, struct hl_error *err)
{
    struct trk_recording_reader *r = trk_recording_open(path, err);
    if (!r)
        return -1;
    uint8_t buf[TRK_RECORDING_MAX_REPORT];
    int64_t t_ns;
    size_t n;
    int rc;
    while ((rc = trk_recording_next(r, &t_ns, buf, sizeof buf, &n, err)) == 1)
        ;
    *count = r->records;
    trk_recording_reader_close(r);
    return rc;
}

int rpl_trace_from_recording(const char *path, struct rpl_trace *out, struct hl_error *err)
{
    uint64_t records = 0;
    if (count_records(path, &records, err) != 0)
        return -1;
    if (records == 0)
        return hl_fail(err, "%s: the recording holds no complete report", path);
    if (records > (uint64_t)SIZE_MAX / sizeof(hl_quatd))
        return hl_fail(err, "%s: %llu records are too many for one trace", path, (unsigned long long)records);

    struct trk_recording_reader *r = trk_recording_open(path, err);
    if (!r)
        return -1;
    struct trace_builder b;
    if (trace_builder_init(&b, out, RPL_TRACE_HMDLOD_CSV, (size_t)records, 0, 0, err) != 0) {
        trk_recording_reader_close(r);
        return -1;
    }
    struct trk_stream *s = malloc(sizeof *s); /* ~1 kB of covariance and parser state: off the stack */
    if (!s) {
        trk_recording_reader_close(r);
        rpl_trace_free(out);
        return hl_fail(err, "%s: out of memory", path);
    }
    trk_stream_init(s, r->info.kind, NULL);

    uint8_t buf[TRK_RECORDING_MAX_REPORT];
    int64_t host_ns, first_ns = 0;
    size_t len;
    int rc, have_first = 0;
    uint64_t rejected = 0, not_later = 0;
    char first_reject[sizeof(struct hl_error)] = "";
    while ((rc = trk_recording_next(r, &host_ns, buf, sizeof buf, &len, err)) == 1) {
        struct hl_error perr;
        int fused = trk_stream_feed(s, buf, len, host_ns, &perr);
        if (fused < 0) {
            /* A report the parser refuses is skipped, as the live driver skips it; the first
             * reason is kept for the note below. */
            if (rejected++ == 0)
                snprintf(first_reject, sizeof first_reject, "%s", perr.msg);
            continue;
        }
        if (fused == 0 || out->count >= b.capacity)
            continue; /* nothing new (a repeated report): no new row */
        if (!have_first) {
            first_ns = s->newest_time_ns;
            have_first = 1;
        }
        struct trk_pose pose;
        trk_stream_pose(s, 0.0, &pose);
        /* Device time from the first fused sample; difference taken in int64 ns before converting
         * so a large device counter does not cost precision — checked, because host times (the
         * HDK's clock) come from the file and two of them can differ by more than int64 holds. */
        int64_t dt_ns;
        if (hl_i64_sub_checked(s->newest_time_ns, first_ns, &dt_ns) != 0) {
            rc = hl_fail(err, "%s: record %llu: time %lld ns is too far from the first sample's %lld ns (more than "
                         "int64 nanoseconds hold)", path, (unsigned long long)r->records,
                         (long long)s->newest_time_ns, (long long)first_ns);
            break;
        }
        double t_s = (double)dt_ns * 1e-9;
        if (out->count > 0 && !(t_s > out->time_s[out->count - 1])) {
            ++not_later; /* the parsers drop backward samples; keep the trace strictly increasing anyway */
            continue;
        }
        trace_builder_push(&b, t_s, hl_q_normalize(pose.orientation), NULL, NULL);
    }
    if (rc >= 0 && out->count > 0 && trace_builder_finish(&b, path, 0, err) != 0) {
        trk_recording_reader_close(r);
        free(s);
        return -1; /* cannot happen: times are strictly increasing; the builder freed the trace */
    }
    int torn = r->torn_tail;
    uint64_t torn_bytes = r->torn_bytes;
    trk_recording_reader_close(r);
    free(s);
    if (rc < 0) {
        rpl_trace_free(out);
        return -1;
    }
    if (out->count == 0) {
        rpl_trace_free(out);
        return hl_fail(err, "%s: none of the %llu reports yielded a sample%s%s", path, (unsigned long long)records,
                       rejected ? "; first rejection: " : "", first_reject);
    }
    if (torn)
        fprintf(stderr, "hmdlod: note: %s: torn tail: %llu bytes ignored (the recording was cut off)\n", path,
                (unsigned long long)torn_bytes);
    if (rejected)
        fprintf(stderr, "hmdlod: note: %s: %llu of %llu reports rejected and skipped; first: %s\n", path,
                (unsigned long long)rejected, (unsigned long long)records, first_reject);
    if (not_later)
        fprintf(stderr, "hmdlod: note: %s: %llu fused samples not later than the one before were skipped\n", path,
                (unsigned long long)not_later);
    return 0;
}
