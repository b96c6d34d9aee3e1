/* Alternated repeats (bench/bench.h): the same few replay sessions run again and again in one
 * process, in an order that turns every other round around, so that ratios between them are
 * measured under the same load and the same process state rather than following run order. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "replay/replay.h"

int bch_alternate_index(int repeat, int k, int n)
{
    return repeat % 2 == 0 ? k : n - 1 - k;
}

void bch_alternate_order(int n, const char *const *names, char *out, size_t size)
{
    /* Two rounds show the whole pattern: forward, then backward, and so on. */
    size_t used = 0;
    out[0] = '\0';
    for (int r = 0; r < 2 && n > 0; ++r) {
        for (int k = 0; k < n && used < size; ++k) {
            int w = snprintf(out + used, size - used, "%s%s", k ? ", " : r ? " | " : "",
                             names[bch_alternate_index(r, k, n)]);
            if (w < 0)
                return;
            used += (size_t)w;
        }
    }
    if (used < size)
        snprintf(out + used, size - used, " | …");
}

int bch_alternate_run(const struct rpl_options *configs, int n, int repeats, struct rpl_summary *sums,
                      const char *who)
{
    char tmp[64];
    if (bch_temp_dir("alternate", tmp, sizeof tmp) != 0)
        return 1;
    int rc = 0;
    for (int r = 0; r < repeats && rc == 0; ++r)
        for (int i = 0; i < n && rc == 0; ++i) {
            int k = bch_alternate_index(r, i, n);
            /* Each session into its own folder: rpl_run writes its files as any replay does (the same
             * work as a session whose output is kept), and the whole folder goes at the end. */
            char out_dir[sizeof tmp + 32];
            snprintf(out_dir, sizeof out_dir, "%s/r%03d-k%02d", tmp, r, k);
            struct rpl_options o = configs[k];
            o.out_dir = out_dir;
            o.frame.quiet = 1;
            if (who)
                fprintf(stderr, "%s: repeat %d of %d, session %d of %d (%s)\n", who, r + 1, repeats, i + 1, n,
                        o.frame.selector);
            struct hl_error err = {{0}};
            if (rpl_run(&o, &sums[r * n + k], &err) != 0) {
                fprintf(stderr, "%s: repeat %d, %s: %s\n", who ? who : "hmdlod", r + 1, o.frame.selector, err.msg);
                rc = 1;
            }
        }
    bch_temp_dir_remove(tmp);
    return rc;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void bch_spread_of(const double *v, int n, struct bch_spread *out)
{
    out->median = out->min = out->max = NAN;
    out->n = 0;
    double sorted[BCH_MAX_REPEATS];
    for (int i = 0; i < n && i < BCH_MAX_REPEATS; ++i)
        if (isfinite(v[i]))
            sorted[out->n++] = v[i];
    if (out->n == 0)
        return;
    qsort(sorted, (size_t)out->n, sizeof sorted[0], compare_doubles);
    int m = out->n / 2;
    /* The middle value, or the mean of the two middle ones: with 2 or 4 repeats the nearest rank
     * would always pick the smaller figure. */
    out->median = out->n % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
    out->min = sorted[0];
    out->max = sorted[out->n - 1];
}

void bch_ratio_spread(const struct rpl_summary *sums, int n, int repeats, int num, int den, struct bch_spread *out)
{
    double ratio[BCH_MAX_REPEATS];
    int count = repeats < BCH_MAX_REPEATS ? repeats : BCH_MAX_REPEATS;
    for (int r = 0; r < count; ++r)
        ratio[r] = sums[r * n + num].frame_ms_mean_after_first / sums[r * n + den].frame_ms_mean_after_first;
    bch_spread_of(ratio, count, out);
}

void bch_mean_spread(const struct rpl_summary *sums, int n, int repeats, int k, struct bch_spread *out)
{
    double mean[BCH_MAX_REPEATS];
    int count = repeats < BCH_MAX_REPEATS ? repeats : BCH_MAX_REPEATS;
    for (int r = 0; r < count; ++r)
        mean[r] = sums[r * n + k].frame_ms_mean_after_first;
    bch_spread_of(mean, count, out);
}
