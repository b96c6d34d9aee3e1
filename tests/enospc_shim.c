/* A full disk, simulated for the fault tests (docs/HARD_CASES.md, "Faults"): an LD_PRELOAD library
 * that lets write(), writev() and pwrite() put HMDLOD_ENOSPC_AFTER bytes in all into files under the
 * folder HMDLOD_ENOSPC_DIR, then fails them with ENOSPC — a short write first where a call straddles
 * the limit, as a real file system does. Everything else passes through untouched. No root, no tmpfs:
 * it runs wherever the tests do. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static pthread_once_t once = PTHREAD_ONCE_INIT;
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static ssize_t (*real_write)(int, const void *, size_t);
static ssize_t (*real_writev)(int, const struct iovec *, int);
static ssize_t (*real_pwrite)(int, const void *, size_t, off_t);
static char dir[PATH_MAX];
static size_t dir_len;
static long long budget = -1; /* -1: off */

static void init(void)
{
    real_write = (ssize_t(*)(int, const void *, size_t))dlsym(RTLD_NEXT, "write");
    real_writev = (ssize_t(*)(int, const struct iovec *, int))dlsym(RTLD_NEXT, "writev");
    real_pwrite = (ssize_t(*)(int, const void *, size_t, off_t))dlsym(RTLD_NEXT, "pwrite");
    const char *d = getenv("HMDLOD_ENOSPC_DIR"), *a = getenv("HMDLOD_ENOSPC_AFTER");
    if (!d || !*d || !a || !*a)
        return;
    if (!realpath(d, dir))
        snprintf(dir, sizeof dir, "%s", d);
    dir_len = strlen(dir);
    budget = strtoll(a, NULL, 10);
    if (budget < 0)
        budget = 0;
}

/* Is fd a file under the folder? (/proc/self/fd names the file as the kernel resolved it.) */
static int watched(int fd)
{
    if (budget < 0)
        return 0;
    char link[64], path[PATH_MAX];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    ssize_t n = readlink(link, path, sizeof path - 1);
    if (n <= 0)
        return 0;
    path[n] = '\0';
    return strncmp(path, dir, dir_len) == 0 && (path[dir_len] == '/' || path[dir_len] == '\0');
}

/* How many of n bytes may go; 0 means fail with ENOSPC. */
static size_t take(size_t n)
{
    pthread_mutex_lock(&mu);
    size_t m = (long long)n > budget ? (size_t)budget : n;
    budget -= (long long)m;
    pthread_mutex_unlock(&mu);
    return m;
}

ssize_t write(int fd, const void *buf, size_t n)
{
    pthread_once(&once, init);
    if (n == 0 || !watched(fd))
        return real_write(fd, buf, n);
    size_t m = take(n);
    if (m == 0) {
        errno = ENOSPC;
        return -1;
    }
    return real_write(fd, buf, m);
}

ssize_t pwrite(int fd, const void *buf, size_t n, off_t offset)
{
    pthread_once(&once, init);
    if (n == 0 || !watched(fd))
        return real_pwrite(fd, buf, n, offset);
    size_t m = take(n);
    if (m == 0) {
        errno = ENOSPC;
        return -1;
    }
    return real_pwrite(fd, buf, m, offset);
}

ssize_t writev(int fd, const struct iovec *iov, int count)
{
    pthread_once(&once, init);
    if (!watched(fd))
        return real_writev(fd, iov, count);
    /* The first buffer with bytes in it, through write(): a short write, as writev may make. */
    for (int i = 0; i < count; ++i)
        if (iov[i].iov_len > 0)
            return write(fd, iov[i].iov_base, iov[i].iov_len);
    return 0;
}
