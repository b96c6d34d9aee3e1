/* Writes a trace in the project's CSV (docs/trace-format.md §1). Atomic: the rows go to a temporary
 * file beside the target, which is renamed over it only once complete and flushed, so a reader
 * never sees a half-written trace posing as a whole one. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "replay/replay.h"

static int write_rows(FILE *f, const struct rpl_trace *t)
{
    fprintf(f, "t_s,qw,qx,qy,qz%s%s\n", t->position_m ? ",px,py,pz" : "", t->gaze_dir ? ",gx,gy,gz" : "");
    for (size_t i = 0; i < t->count; ++i) {
        /* %.9f keeps ns time resolution; %.17g round-trips every double exactly. */
        hl_quatd q = t->orientation[i];
        fprintf(f, "%.9f,%.17g,%.17g,%.17g,%.17g", t->time_s[i], q.w, q.x, q.y, q.z);
        if (t->position_m)
            fprintf(f, ",%.17g,%.17g,%.17g", t->position_m[i].x, t->position_m[i].y, t->position_m[i].z);
        if (t->gaze_dir)
            fprintf(f, ",%.17g,%.17g,%.17g", t->gaze_dir[i].x, t->gaze_dir[i].y, t->gaze_dir[i].z);
        if (fputc('\n', f) == EOF)
            return -1;
    }
    return ferror(f) ? -1 : 0;
}

int rpl_trace_write_csv(const struct rpl_trace *t, const char *path, struct hl_error *err)
{
    if (!t || t->count == 0)
        return hl_fail(err, "%s: empty trace: nothing to write", path);
    struct hl_out o;
    if (hl_out_open(&o, path, err) != 0)
        return -1;
    (void)write_rows(o.f, t); /* a failed write is the commit's error, with its reason */
    if (hl_out_commit(&o, err) != 0)
        return -1;
    return 0;
}
