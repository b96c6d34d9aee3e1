/* Opening and reading input files with bounded resources: every loader in the project comes through
 * here so that none can block on a FIFO with no writer, read a device such as /dev/zero forever, or
 * let a file's size decide its memory beyond a stated limit (docs/HARD_CASES.md, "inputs"). */
#include "base/base.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

uint64_t hl_file_max_bytes(void)
{
    const char *v = getenv(HL_FILE_MAX_BYTES_ENV);
    if (v && *v) {
        char *end = NULL;
        errno = 0;
        unsigned long long n = strtoull(v, &end, 10);
        /* A malformed value must not silently lift or drop the guard: it falls back to the default. */
        if (errno == 0 && end != v && *end == '\0' && n > 0 && v[0] != '-')
            return (uint64_t)n;
    }
    return HL_FILE_DEFAULT_MAX_BYTES;
}

static const char *file_kind(mode_t m)
{
    return S_ISDIR(m)    ? "a directory"
           : S_ISFIFO(m) ? "a FIFO"
           : S_ISCHR(m)  ? "a character device"
           : S_ISBLK(m)  ? "a block device"
           : S_ISSOCK(m) ? "a socket"
                         : "not a plain file";
}

FILE *hl_file_open_read(const char *path, uint64_t *size_out, struct hl_error *err)
{
    if (!path) {
        hl_fail(err, "file: no path");
        return NULL;
    }
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer before fstat could
     * refuse it. It is cleared again below so that reads of the regular file behave normally. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        hl_fail(err, "%s: cannot open: %s", path, strerror(e));
        errno = e; /* callers tell a missing file (ENOENT) from others */
        return NULL;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        hl_fail(err, "%s: cannot stat: %s", path, strerror(e));
        return NULL;
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        hl_fail(err, "%s: not a regular file (%s)", path, file_kind(st.st_mode));
        errno = EINVAL;
        return NULL;
    }
    int flags = fcntl(fd, F_GETFL);
    FILE *f = flags >= 0 && fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        int e = errno;
        close(fd);
        hl_fail(err, "%s: cannot open: %s", path, strerror(e));
        return NULL;
    }
    if (size_out)
        *size_out = (uint64_t)st.st_size;
    return f;
}

/* "2 GiB", "1 MiB", "65536 bytes": limits read as people state them. */
static void format_size(uint64_t n, char *buf, size_t size)
{
    static const char *const units[] = {"GiB", "MiB", "KiB"};
    for (int i = 0; i < 3; ++i) {
        uint64_t unit = (uint64_t)1 << (30 - 10 * i);
        if (n >= unit && n % unit == 0) {
            snprintf(buf, size, "%llu %s", (unsigned long long)(n / unit), units[i]);
            return;
        }
    }
    snprintf(buf, size, "%llu bytes", (unsigned long long)n);
}

int hl_file_read_all(const char *path, uint64_t max_bytes, char **buf_out, size_t *len_out, struct hl_error *err)
{
    *buf_out = NULL;
    if (len_out)
        *len_out = 0;
    int default_limit = max_bytes == 0;
    if (default_limit)
        max_bytes = hl_file_max_bytes();
    if (max_bytes > (uint64_t)SIZE_MAX - 2)
        max_bytes = (uint64_t)SIZE_MAX - 2;
    uint64_t size = 0;
    FILE *f = hl_file_open_read(path, &size, err);
    if (!f)
        return -1;
    char limit[32];
    format_size(max_bytes, limit, sizeof limit);
    const char *hint = default_limit ? " (raise it with hmdlod --max-input-bytes N, or " HL_FILE_MAX_BYTES_ENV ")" : "";
    if (size > max_bytes) {
        fclose(f);
        return hl_fail(err, "%s: file too large: %llu bytes, more than the %s limit%s", path,
                       (unsigned long long)size, limit, hint);
    }
    /* Sized from fstat, grown geometrically only if the file grows while being read, and never past
     * max_bytes + 1 (the one byte past the limit is how growth beyond it is caught). */
    size_t cap = (size_t)size + 1, len = 0;
    char *buf = malloc(cap + 1);
    if (!buf) {
        fclose(f);
        return hl_fail(err, "%s: out of memory for %llu bytes", path, (unsigned long long)size);
    }
    for (;;) {
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (len > max_bytes || got == 0)
            break;
        if (len == cap) {
            size_t most = (size_t)max_bytes + 1;
            size_t ncap = cap > most / 2 ? most : cap * 2; /* no cap * 2 that could wrap */
            char *nb = realloc(buf, ncap + 1);
            if (!nb) {
                free(buf);
                fclose(f);
                return hl_fail(err, "%s: out of memory reading the file", path);
            }
            buf = nb;
            cap = ncap;
        }
    }
    int failed = ferror(f);
    int e = errno;
    fclose(f);
    if (failed) {
        free(buf);
        return hl_fail(err, "%s: byte %zu: read failed: %s", path, len, strerror(e));
    }
    if (len > max_bytes) {
        free(buf);
        return hl_fail(err, "%s: file too large: it grew past the %s limit while being read%s", path, limit, hint);
    }
    buf[len] = '\0';
    *buf_out = buf;
    if (len_out)
        *len_out = len;
    return 0;
}
