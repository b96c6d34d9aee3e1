/* The live session's bookkeeping (live.c): growing series of per-frame times and their statistics,
 * and CSV files written beside their name and renamed when complete (the head trace, the log). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "replay/live_internal.h"

/* Growing arrays of per-frame times (a session without --frames runs until stopped). */
int rpl_live_series_push(struct rpl_live_series *s, double x)
{
    if (s->n == s->cap) {
        long cap = s->cap ? 2 * s->cap : 1024;
        double *v = realloc(s->v, (size_t)cap * sizeof *v);
        if (!v)
            return -1;
        s->v = v, s->cap = cap;
    }
    s->v[s->n++] = x;
    return 0;
}
static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
/* Mean, stddev (population), median, p99 (nearest rank) and max; sorts in place. */
void rpl_live_series_stats(struct rpl_live_series *s, double *mean, double *stddev, double *median, double *p99, double *max)
{
    double sum = 0, sq = 0;
    for (long i = 0; i < s->n; ++i)
        sum += s->v[i];
    double m = s->n ? sum / (double)s->n : 0;
    for (long i = 0; i < s->n; ++i)
        sq += (s->v[i] - m) * (s->v[i] - m);
    if (s->n > 0) /* an empty series has no array: qsort's pointer must not be NULL even for 0 items */
        qsort(s->v, (size_t)s->n, sizeof *s->v, compare_double);
    if (mean)
        *mean = m;
    if (stddev)
        *stddev = s->n ? sqrt(sq / (double)s->n) : 0;
    if (median)
        *median = s->n ? (s->n % 2 ? s->v[s->n / 2] : 0.5 * (s->v[s->n / 2 - 1] + s->v[s->n / 2])) : 0;
    if (p99) {
        long k = (long)ceil(0.99 * (double)s->n) - 1;
        *p99 = s->n ? s->v[k < 0 ? 0 : k] : 0;
    }
    if (max)
        *max = s->n ? s->v[s->n - 1] : 0;
}

/* The head trace of the session, written beside its name and renamed when complete. */
int rpl_live_record_open(struct rpl_live_record *r, const char *path, const char *header, struct hl_error *err)
{
    memset(r, 0, sizeof *r);
    if (!path)
        return 0;
    if (snprintf(r->path, sizeof r->path, "%s", path) >= (int)sizeof r->path ||
        snprintf(r->tmp, sizeof r->tmp, "%s.partial", path) >= (int)sizeof r->tmp)
        return hl_fail(err, "--record %s: path too long", path);
    r->f = fopen(r->tmp, "w");
    if (!r->f)
        return hl_fail(err, "--record %s: cannot write %s: %s", path, r->tmp, strerror(errno));
    fputs(header, r->f);
    r->t0_s = -1;
    return 0;
}
void rpl_live_record_row(struct rpl_live_record *r, const struct trk_pose *p)
{
    if (!r->f || r->paused)
        return;
    if (r->t0_s < 0)
        r->t0_s = p->time_s;
    hl_quatd q = p->orientation;
    fprintf(r->f, "%.6f,%.9f,%.9f,%.9f,%.9f\n", p->time_s - r->t0_s, q.w, q.x, q.y, q.z);
    r->rows++;
}
int rpl_live_record_commit(struct rpl_live_record *r, struct hl_error *err)
{
    if (!r->f)
        return 0;
    int bad = ferror(r->f);
    bad |= fclose(r->f) != 0;
    r->f = NULL;
    if (bad || rename(r->tmp, r->path) != 0) {
        remove(r->tmp);
        return hl_fail(err, "--record %s: writing failed", r->path);
    }
    return 0;
}
void rpl_live_record_abort(struct rpl_live_record *r)
{
    if (r->f) {
        fclose(r->f);
        remove(r->tmp);
        r->f = NULL;
    }
}
