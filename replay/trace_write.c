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
    size_t n = strlen(path);
    char *tmp = malloc(n + 16);
    if (!tmp)
        return hl_fail(err, "%s: out of memory", path);
    memcpy(tmp, path, n);
    memcpy(tmp + n, ".tmp.XXXXXX", 12);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        int e = errno;
        free(tmp);
        return hl_fail(err, "%s: cannot create a temporary file beside it: %s", path, strerror(e));
    }
    (void)fchmod(fd, 0644); /* mkstemp makes 0600; a trace is an ordinary output file */
    FILE *f = fdopen(fd, "w");
    if (!f) {
        close(fd);
        unlink(tmp);
        free(tmp);
        return hl_fail(err, "%s: fdopen: %s", path, strerror(errno));
    }
    int rc = write_rows(f, t);
    if (fflush(f) != 0 || fsync(fileno(f)) != 0)
        rc = -1;
    int e = errno;
    if (fclose(f) != 0 && rc == 0) {
        rc = -1;
        e = errno;
    }
    if (rc == 0 && rename(tmp, path) != 0) {
        rc = -1;
        e = errno;
    }
    if (rc != 0) {
        unlink(tmp);
        free(tmp);
        return hl_fail(err, "%s: write failed: %s", path, strerror(e));
    }
    free(tmp);
    return 0;
}
