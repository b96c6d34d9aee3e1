/* The live session's bookkeeping (live.c): per-frame times and their statistics in bounded memory,
 * and CSV files written beside their name and renamed when complete (the head trace, the log). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/base.h"
#include "live/live.h"

/* Log-spaced bins: bin k holds [LO·R^k, LO·R^(k+1)); the first also takes everything below LO, the
 * last everything above. R = 1.001, so a bin's centre is within 0.05 % of any value in it. */
#define SERIES_LO_MS 1e-3
#define SERIES_RATIO 1.001
#define SERIES_BINS 18432 /* ceil(ln(1e8) / ln(1.001)) = 18430: 1 µs … 100 s */

static long bin_of(double x_ms)
{
    if (!(x_ms > SERIES_LO_MS))
        return 0;
    double k = floor(log(x_ms / SERIES_LO_MS) / log(SERIES_RATIO));
    return k >= SERIES_BINS - 1 ? SERIES_BINS - 1 : (long)k;
}
static double bin_centre_ms(long k) { return SERIES_LO_MS * pow(SERIES_RATIO, (double)k + 0.5); }

static void fold_into_bins(struct liv_series *s, double x) { s->bins[bin_of(x)]++; }

int liv_series_push(struct liv_series *s, double x)
{
    if (!s->v && !(s->v = malloc(LIV_SERIES_EXACT * sizeof *s->v)))
        return -1;
    if (s->n == LIV_SERIES_EXACT && !s->bins) { /* a long session: from here on, bins */
        if (!(s->bins = calloc(SERIES_BINS, sizeof *s->bins)))
            return -1;
        for (long i = 0; i < s->n; ++i)
            fold_into_bins(s, s->v[i]);
    }
    if (s->bins)
        fold_into_bins(s, x);
    else
        s->v[s->n] = x;
    s->n++;
    double d = x - s->mean; /* Welford: exact mean and variance in one pass */
    s->mean += d / (double)s->n;
    s->m2 += d * (x - s->mean);
    if (s->n == 1 || x > s->max)
        s->max = x;
    return 0;
}

/* The value of nearest rank `rank` (1-based) from the bins, clamped to the exact maximum. */
static double binned_rank(const struct liv_series *s, long rank)
{
    long seen = 0;
    for (long k = 0; k < SERIES_BINS; ++k) {
        seen += s->bins[k];
        if (seen >= rank)
            return fmin(bin_centre_ms(k), s->max);
    }
    return s->max;
}

/* Mean, stddev (population), median, p99 (nearest rank) and max. Exact values are sorted in place. */
void liv_series_stats(struct liv_series *s, double *mean, double *stddev, double *median, double *p99, double *max)
{
    long n = s->n, k99 = (long)ceil(0.99 * (double)n);
    double med = 0, q99 = 0;
    if (n > 0 && s->bins) {
        med = n % 2 ? binned_rank(s, n / 2 + 1) : 0.5 * (binned_rank(s, n / 2) + binned_rank(s, n / 2 + 1));
        q99 = binned_rank(s, k99 < 1 ? 1 : k99);
    } else if (n > 0) {
        hl_sort_doubles(s->v, (size_t)n);
        med = n % 2 ? s->v[n / 2] : 0.5 * (s->v[n / 2 - 1] + s->v[n / 2]);
        q99 = s->v[k99 < 1 ? 0 : k99 - 1];
    }
    if (mean)
        *mean = n ? s->mean : 0;
    if (stddev)
        *stddev = n ? sqrt(fmax(s->m2, 0.0) / (double)n) : 0;
    if (median)
        *median = med;
    if (p99)
        *p99 = q99;
    if (max)
        *max = n ? s->max : 0;
}

void liv_series_free(struct liv_series *s)
{
    free(s->v), free(s->bins);
    memset(s, 0, sizeof *s);
}

/* The head trace of the session (and the --log), written beside its name and renamed when complete;
 * each row is flushed as a whole, so a failed write leaves a prefix of whole rows to keep. */
int liv_record_open(struct liv_record *r, const char *path, const char *header, struct hl_error *err)
{
    memset(r, 0, sizeof *r);
    if (!path)
        return 0;
    if (snprintf(r->path, sizeof r->path, "%s", path) >= (int)sizeof r->path)
        return hl_fail(err, "%s: path too long", path);
    if (hl_out_open(&r->out, path, err) != 0)
        return -1;
    r->f = r->out.f;
    r->t0_s = -1;
    fputs(header, r->f);
    if (hl_out_mark(&r->out, err) != 0) {
        r->f = NULL;
        hl_out_abort(&r->out); /* not even the header: no file at all */
        return -1;
    }
    return 0;
}
void liv_record_row(struct liv_record *r, const struct trk_pose *p)
{
    if (!r->f || r->paused)
        return;
    if (r->rows > 0 && !(p->time_s > r->last_t_s)) {
        r->dropped_rows++;
        return;
    }
    if (r->t0_s < 0)
        r->t0_s = p->time_s;
    r->last_t_s = p->time_s;
    hl_quatd q = p->orientation;
    fprintf(r->f, "%.6f,%.9f,%.9f,%.9f,%.9f\n", p->time_s - r->t0_s, q.w, q.x, q.y, q.z);
    r->rows++;
}
int liv_record_end_row(struct liv_record *r, struct hl_error *err)
{
    if (!r->f)
        return 0;
    struct hl_error werr;
    if (hl_out_mark(&r->out, &werr) == 0)
        return 0;
    r->f = NULL;
    long kept = r->rows - 1; /* the row just written is the one that failed */
    if (hl_out_commit_prefix(&r->out, err) != 0)
        return -1;
    return hl_fail(err, "%s; the session stopped, and the file holds its first %ld rows (incomplete)", werr.msg,
                   kept < 0 ? 0 : kept);
}
int liv_record_commit(struct liv_record *r, struct hl_error *err)
{
    if (!r->f)
        return 0;
    r->f = NULL;
    return hl_out_commit(&r->out, err);
}
void liv_record_abort(struct liv_record *r)
{
    r->f = NULL;
    hl_out_abort(&r->out);
}
