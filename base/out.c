/* Writing output files: one temporary beside the final name, every write checked, then one rename
 * (base.h, "output files"). The temporary is created with O_EXCL|O_NOFOLLOW, so a symlink planted at
 * its name cannot redirect the data, and rename(2) replaces a symlink at the final name instead of
 * following it (issue 17 item 8). Writes go through a stdio cookie that keeps the errno of the first
 * failed write, so a full disk is reported as "No space left on device", not as a vague stream error. */
#define _GNU_SOURCE
#include "base/base.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* What the cookie stream knows: bytes the kernel accepted, and why the first refused write failed. */
struct out_state {
    int fd;
    int write_errno;
    uint64_t written;
};

static ssize_t cookie_write(void *cookie, const char *buf, size_t size)
{
    struct out_state *s = cookie;
    size_t done = 0;
    while (done < size) {
        ssize_t n = write(s->fd, buf + done, size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            if (!s->write_errno)
                s->write_errno = n < 0 ? errno : EIO;
            s->written += done;
            errno = s->write_errno;
            return done > 0 ? (ssize_t)done : -1;
        }
        done += (size_t)n;
    }
    s->written += done;
    return (ssize_t)size;
}

static int cookie_close(void *cookie)
{
    (void)cookie; /* the descriptor is hl_out's: closed after the sync, or kept to cut back a prefix */
    return 0;
}

static void out_free(struct hl_out *o)
{
    free(o->path);
    free(o->tmp);
    o->path = o->tmp = NULL;
    o->f = NULL;
    o->fd = -1;
}

/* A name no one else uses beside path: pid, clock and a counter (O_EXCL settles any collision). */
static void tmp_name(char *tmp, size_t size, const char *path, unsigned attempt)
{
    static unsigned counter; /* atomic: outputs may be opened on several threads */
    unsigned c = __atomic_add_fetch(&counter, 1, __ATOMIC_RELAXED);
    uint64_t x = (uint64_t)hl_clock_now_ns() ^ ((uint64_t)getpid() << 32) ^ (uint64_t)(c * 2654435761u) ^ attempt;
    snprintf(tmp, size, "%s.tmp.%06llx", path, (unsigned long long)(x & 0xffffff));
}

int hl_out_open(struct hl_out *o, const char *path, struct hl_error *err)
{
    memset(o, 0, sizeof *o);
    o->fd = -1;
    if (!path || !*path)
        return hl_fail(err, "output: no path");
    size_t n = strlen(path);
    o->path = malloc(n + 1);
    o->tmp = malloc(n + 16);
    struct out_state *s = malloc(sizeof *s);
    if (!o->path || !o->tmp || !s) {
        free(s);
        out_free(o);
        return hl_fail(err, "%s: out of memory", path);
    }
    memcpy(o->path, path, n + 1);
    int fd = -1;
    for (unsigned attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        tmp_name(o->tmp, n + 16, path, attempt);
        fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd < 0 && errno != EEXIST)
            break;
    }
    if (fd < 0) {
        int e = errno;
        free(s);
        out_free(o);
        return hl_fail(err, "%s: cannot create a file beside it: %s", path, strerror(e));
    }
    s->fd = fd, s->write_errno = 0, s->written = 0;
    cookie_io_functions_t io = {NULL, cookie_write, NULL, cookie_close};
    o->f = fopencookie(s, "w", io);
    if (!o->f) {
        close(fd);
        unlink(o->tmp);
        free(s);
        out_free(o);
        return hl_fail(err, "%s: out of memory", path);
    }
    o->fd = fd;
    o->state_ = s;
    return 0;
}

/* errno of the first failed write, or of the failing call itself. */
static int out_errno(const struct hl_out *o, int fallback)
{
    const struct out_state *s = o->state_;
    return s && s->write_errno ? s->write_errno : fallback ? fallback : EIO;
}

/* Flushes and closes the stream; the reason of the first failure in *why. */
static int out_close_stream(struct hl_out *o, int *why)
{
    int failed = 0;
    errno = 0;
    if (fflush(o->f) != 0 || ferror(o->f))
        failed = 1, *why = out_errno(o, errno);
    if (fclose(o->f) != 0 && !failed)
        failed = 1, *why = out_errno(o, errno);
    o->f = NULL;
    free(o->state_);
    o->state_ = NULL;
    return failed ? -1 : 0;
}

/* The rename made durable: a folder that refuses fsync is no error. */
static void sync_dir(const char *path)
{
    const char *slash = strrchr(path, '/');
    char dir[4096];
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if ((size_t)(slash - path) < sizeof dir)
        snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
    else
        return;
    int dfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        (void)fsync(dfd);
        close(dfd);
    }
}

static int out_fail(struct hl_out *o, struct hl_error *err, const char *what, int e)
{
    hl_fail(err, "%s: %s: %s", o->path, what, strerror(e));
    if (o->fd >= 0)
        close(o->fd);
    if (!o->published)
        unlink(o->tmp);
    out_free(o);
    errno = e; /* callers that keep errno (the analysis cache's note) still see why */
    return -1;
}

int hl_out_close(struct hl_out *o, struct hl_error *err)
{
    if (!o->path)
        return hl_fail(err, "output: not open");
    if (o->closed)
        return 0;
    int why = 0;
    if (o->f && out_close_stream(o, &why) != 0)
        return out_fail(o, err, "write failed", why);
    if (fsync(o->fd) != 0 && errno != EINVAL && errno != EROFS) /* EINVAL: a file system without fsync */
        return out_fail(o, err, "write failed (fsync)", errno);
    if (close(o->fd) != 0) {
        int e = errno;
        o->fd = -1;
        return out_fail(o, err, "write failed (close)", e);
    }
    o->fd = -1;
    o->closed = 1;
    return 0;
}

int hl_out_commit(struct hl_out *o, struct hl_error *err)
{
    if (hl_out_close(o, err) != 0)
        return -1;
    if (!o->published) {
        if (rename(o->tmp, o->path) != 0)
            return out_fail(o, err, "cannot rename into place", errno);
        sync_dir(o->path);
    }
    out_free(o);
    return 0;
}

void hl_out_abort(struct hl_out *o)
{
    if (!o->path)
        return;
    if (o->f) {
        int why = 0;
        (void)out_close_stream(o, &why);
    }
    if (o->fd >= 0)
        close(o->fd);
    if (!o->published)
        unlink(o->tmp);
    out_free(o);
}

int hl_out_mark(struct hl_out *o, struct hl_error *err)
{
    errno = 0;
    if (!o->f || fflush(o->f) != 0 || ferror(o->f))
        return hl_fail(err, "%s: write failed: %s", o->path, strerror(out_errno(o, errno)));
    o->marked = ((const struct out_state *)o->state_)->written;
    o->records++;
    return 0;
}

int hl_out_commit_prefix(struct hl_out *o, struct hl_error *err)
{
    if (!o->path)
        return hl_fail(err, "output: not open");
    if (o->f) {
        int why = 0;
        (void)out_close_stream(o, &why); /* whatever it still writes past the mark is cut below */
    }
    if (ftruncate(o->fd, (off_t)o->marked) != 0)
        return out_fail(o, err, "cannot cut back to the last complete record", errno);
    return hl_out_commit(o, err);
}

int hl_out_publish(struct hl_out *o, struct hl_error *err)
{
    if (!o->path || o->published)
        return 0;
    int why = 0;
    if (o->f && fflush(o->f) != 0)
        why = out_errno(o, errno);
    if (!why && fsync(o->fd) != 0 && errno != EINVAL && errno != EROFS)
        why = errno;
    if (why) {
        if (o->f) {
            fclose(o->f);
            o->f = NULL;
            free(o->state_);
            o->state_ = NULL;
        }
        return out_fail(o, err, "write failed", why);
    }
    if (rename(o->tmp, o->path) != 0) {
        int e = errno;
        if (o->f) {
            fclose(o->f);
            o->f = NULL;
            free(o->state_);
            o->state_ = NULL;
        }
        return out_fail(o, err, "cannot rename into place", e);
    }
    sync_dir(o->path);
    o->published = 1;
    return 0;
}

int hl_out_write_all(const char *path, const void *data, size_t size, struct hl_error *err)
{
    struct hl_out o;
    if (hl_out_open(&o, path, err) != 0)
        return -1;
    if (size > 0 && fwrite(data, 1, size, o.f) != size) {
        int why = 0;
        (void)out_close_stream(&o, &why);
        return out_fail(&o, err, "write failed", why ? why : EIO);
    }
    return hl_out_commit(&o, err);
}

int hl_dir_make(const char *path, struct hl_error *err)
{
    if (!path || !*path)
        return hl_fail(err, "folder: no path");
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return hl_fail(err, "%s: cannot create the folder: %s", path, strerror(errno));
    /* Opened without following a link: a symlink planted where the program makes its own folder
     * would send every file written "inside" it somewhere else. */
    int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        struct stat st;
        if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode))
            return hl_fail(err, "%s: is a symbolic link, not a folder: refusing to write through it", path);
        if (e == ENOTDIR)
            return hl_fail(err, "%s: exists and is not a folder", path);
        return hl_fail(err, "%s: cannot open the folder: %s", path, strerror(e));
    }
    close(fd);
    if (access(path, W_OK) != 0)
        return hl_fail(err, "%s: not a writable folder", path);
    return 0;
}
