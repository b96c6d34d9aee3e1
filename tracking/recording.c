/* Raw recordings: the reports exactly as received, append-only, each record checksummed, so that a
 * session can be replayed through the parser and fusion (docs/raw-recording.md has the layout, the
 * flush policy and what the reader tolerates). */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "tracking/tracking.h"

#include <zlib.h>

/* CRC-32: zlib's (thread-safe, its tables built at compile time). */
uint32_t trk_crc32(uint32_t crc, const void *data, size_t length) { return (uint32_t)crc32_z(crc, data, length); }

/* ---- little-endian fields ---------------------------------------------------------------------- */
static void put_i64(uint8_t *p, int64_t v) { hl_le_put_u64(p, (uint64_t)v); }
static int64_t get_i64(const uint8_t *p)
{
    return (int64_t)hl_le_get_u64(p); /* two's complement: implementation-defined in C11, exact on every target we build */
}

/* Header layout (offsets), version 1. */
enum {
    H_MAGIC = 0, H_VERSION = 8, H_HEADER_SIZE = 10, H_KIND = 12, H_VID = 14, H_PID = 16, H_FLAGS = 18,
    H_HOST_START = 20, H_WALL_START = 28, H_NAME = 36, H_CRC = 100
};
/* Record layout: length, time, report, CRC. */
enum { R_LENGTH = 0, R_TIME = 4, R_REPORT = 12 };

#define KIND_LAST TRK_DEVICE_HDK

/* ---- writer ------------------------------------------------------------------------------------ */
struct trk_recording {
    int fd;
    int broken;         /* a write failed: cut back to the last whole record; refuse more */
    uint64_t records;
    uint64_t bytes;     /* header and whole records: where the file ends if a write fails */
    struct hl_out out;  /* created beside the path, published (renamed into place) after the header */
    char *path;
    uint8_t buf[TRK_RECORDING_RECORD_OVERHEAD + TRK_RECORDING_MAX_REPORT]; /* one record, reused */
};

/* write() until done. A regular file normally takes the whole record in the first call; the loop is
 * for short writes (disk nearly full) and EINTR. */
static int write_all(int fd, const uint8_t *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

struct trk_recording *trk_recording_create(const char *path, enum trk_device_kind kind, uint16_t vid, uint16_t pid,
                                           const char *name, struct hl_error *err)
{
    if (!path || !*path) {
        hl_fail(err, "raw recording: no path");
        return NULL;
    }
    if ((int)kind < 0 || kind > KIND_LAST) {
        hl_fail(err, "%s: unknown device kind %d", path, (int)kind);
        return NULL;
    }
    struct trk_recording *rec = calloc(1, sizeof *rec);
    size_t path_len = strlen(path);
    if (!rec || !(rec->path = malloc(path_len + 1))) {
        free(rec);
        hl_fail(err, "%s: out of memory", path);
        return NULL;
    }
    memcpy(rec->path, path, path_len + 1);

    uint8_t h[TRK_RECORDING_HEADER_SIZE];
    memset(h, 0, sizeof h);
    memcpy(h + H_MAGIC, TRK_RECORDING_MAGIC, 8);
    hl_le_put_u16(h + H_VERSION, TRK_RECORDING_VERSION);
    hl_le_put_u16(h + H_HEADER_SIZE, TRK_RECORDING_HEADER_SIZE);
    hl_le_put_u16(h + H_KIND, (uint16_t)kind);
    hl_le_put_u16(h + H_VID, vid);
    hl_le_put_u16(h + H_PID, pid);
    hl_le_put_u16(h + H_FLAGS, 0);
    put_i64(h + H_HOST_START, hl_clock_now_ns());
    struct timespec wall;
    clock_gettime(CLOCK_REALTIME, &wall);
    put_i64(h + H_WALL_START, (int64_t)wall.tv_sec * 1000000000 + wall.tv_nsec);
    if (name) {
        size_t n = strlen(name);
        memcpy(h + H_NAME, name, n < TRK_RECORDING_NAME_SIZE ? n : TRK_RECORDING_NAME_SIZE);
    }
    hl_le_put_u32(h + H_CRC, trk_crc32(0, h, H_CRC));

    /* hl_out: a fresh file beside path (never one reached through a planted link), renamed into place
     * once the header is on disk, so a recording is under its name from then on even if the process
     * dies, and a file without a complete header is never seen under it. */
    if (hl_out_open(&rec->out, path, err) != 0) {
        free(rec->path);
        free(rec);
        return NULL;
    }
    rec->fd = rec->out.fd;
    if (write_all(rec->fd, h, sizeof h) != 0) {
        hl_fail(err, "%s: byte 0: cannot write the header: %s", path, strerror(errno));
        hl_out_abort(&rec->out); /* no recording at all, and whatever was at path is kept */
        free(rec->path);
        free(rec);
        return NULL;
    }
    if (hl_out_publish(&rec->out, err) != 0) {
        free(rec->path);
        free(rec);
        return NULL;
    }
    rec->bytes = sizeof h;
    return rec;
}

int trk_recording_append(struct trk_recording *rec, int64_t host_time_ns, const uint8_t *report, size_t length,
                         struct hl_error *err)
{
    if (rec->broken)
        return hl_fail(err, "%s: an earlier write failed; the recording is closed to appends", rec->path);
    if (!report || length == 0 || length > TRK_RECORDING_MAX_REPORT)
        return hl_fail(err, "%s: report of %zu bytes (must be 1..%d)", rec->path, length, TRK_RECORDING_MAX_REPORT);
    /* The whole record is built first and handed to the kernel in one write(): a process killed at
     * any moment leaves either the whole record or (on a short write) a prefix of it — and only of
     * the last one. No stdio buffer, so nothing appended is lost when the process dies. */
    uint8_t *b = rec->buf;
    hl_le_put_u32(b + R_LENGTH, (uint32_t)length);
    put_i64(b + R_TIME, host_time_ns);
    memcpy(b + R_REPORT, report, length);
    hl_le_put_u32(b + R_REPORT + length, trk_crc32(0, b, R_REPORT + length));
    size_t total = TRK_RECORDING_RECORD_OVERHEAD + length;
    if (write_all(rec->fd, b, total) != 0) {
        int e = errno;
        rec->broken = 1;
        /* A short write (disk full) leaves a torn record: cut it off, so the file ends on a whole
         * record and every reader takes it as it is (docs/raw-recording.md, "disk full"). */
        int cut = ftruncate(rec->fd, (off_t)rec->bytes) == 0;
        return hl_fail(err, "%s: record %llu: write failed: %s; the recording stopped and holds the %llu complete "
                       "records before it%s", rec->path, (unsigned long long)rec->records, strerror(e),
                       (unsigned long long)rec->records, cut ? " (incomplete)" : ", then a torn one");
    }
    rec->bytes += total;
    ++rec->records;
    return 0;
}

uint64_t trk_recording_records(const struct trk_recording *rec) { return rec ? rec->records : 0; }

int trk_recording_close(struct trk_recording *rec, int sync_to_disk, struct hl_error *err)
{
    if (!rec)
        return 0;
    int rc = rec->broken ? hl_fail(err, "%s: a write failed; the recording holds the %llu complete records before it "
                                        "(incomplete)", rec->path, (unsigned long long)rec->records)
                         : 0;
    if (sync_to_disk && fsync(rec->fd) != 0 && rc == 0)
        rc = hl_fail(err, "%s: fsync: %s", rec->path, strerror(errno));
    rec->out.fd = -1; /* closed here: the file is already in place, hl_out only frees its names */
    hl_out_abort(&rec->out);
    if (close(rec->fd) != 0 && rc == 0)
        rc = hl_fail(err, "%s: close: %s", rec->path, strerror(errno));
    free(rec->path);
    free(rec);
    return rc;
}

/* ---- reader ------------------------------------------------------------------------------------ */
void trk_recording_reader_close(struct trk_recording_reader *r)
{
    if (!r)
        return;
    if (r->file)
        fclose(r->file);
    free(r->path);
    free(r);
}

static int read_at(struct trk_recording_reader *r, uint64_t offset, uint8_t *p, size_t n)
{
    if (fseeko(r->file, (off_t)offset, SEEK_SET) != 0)
        return -1;
    return fread(p, 1, n, r->file) == n ? 0 : -1;
}

struct trk_recording_reader *trk_recording_open(const char *path, struct hl_error *err)
{
    struct trk_recording_reader *r = calloc(1, sizeof *r);
    size_t path_len = path ? strlen(path) : 0;
    if (!path || !r || !(r->path = malloc(path_len + 1))) {
        free(r);
        hl_fail(err, "%s: %s", path ? path : "raw recording", path ? "out of memory" : "no path");
        return NULL;
    }
    memcpy(r->path, path, path_len + 1);
    /* Read record by record (memory does not grow with the file); a FIFO or device is refused here. */
    r->file = hl_file_open_read(path, &r->file_size, err);
    if (!r->file)
        goto fail;

    uint8_t h[TRK_RECORDING_HEADER_SIZE];
    size_t got = fread(h, 1, sizeof h, r->file);
    size_t magic_n = got < 8 ? got : 8;
    if (memcmp(h, TRK_RECORDING_MAGIC, magic_n) != 0 || got == 0) {
        hl_fail(err, "%s: byte 0: not an hmdlod raw recording (no \"%s\" magic)", path, TRK_RECORDING_MAGIC);
        goto fail;
    }
    if (got >= H_VERSION + 2 && hl_le_get_u16(h + H_VERSION) != TRK_RECORDING_VERSION) {
        hl_fail(err, "%s: byte %d: format version %u is not supported (this reader knows %d)", path, H_VERSION,
                hl_le_get_u16(h + H_VERSION), TRK_RECORDING_VERSION);
        goto fail;
    }
    if (got < sizeof h) {
        hl_fail(err, "%s: byte %zu: file ends inside the %d-byte header", path, got, TRK_RECORDING_HEADER_SIZE);
        goto fail;
    }
    if (hl_le_get_u16(h + H_HEADER_SIZE) != TRK_RECORDING_HEADER_SIZE) {
        hl_fail(err, "%s: byte %d: header size %u, version 1 has %d", path, H_HEADER_SIZE, hl_le_get_u16(h + H_HEADER_SIZE),
                TRK_RECORDING_HEADER_SIZE);
        goto fail;
    }
    if (hl_le_get_u32(h + H_CRC) != trk_crc32(0, h, H_CRC)) {
        hl_fail(err, "%s: byte %d: header CRC mismatch (the header is corrupt)", path, H_CRC);
        goto fail;
    }
    unsigned kind = hl_le_get_u16(h + H_KIND);
    if (kind > KIND_LAST) {
        hl_fail(err, "%s: byte %d: unknown device kind %u", path, H_KIND, kind);
        goto fail;
    }
    r->info.version = hl_le_get_u16(h + H_VERSION);
    r->info.kind = (enum trk_device_kind)kind;
    r->info.vid = hl_le_get_u16(h + H_VID);
    r->info.pid = hl_le_get_u16(h + H_PID);
    memcpy(r->info.name, h + H_NAME, TRK_RECORDING_NAME_SIZE);
    r->info.name[TRK_RECORDING_NAME_SIZE] = '\0';
    r->info.host_start_ns = get_i64(h + H_HOST_START);
    r->info.wall_start_unix_ns = get_i64(h + H_WALL_START);
    r->offset = TRK_RECORDING_HEADER_SIZE;
    return r;
fail:
    trk_recording_reader_close(r);
    return NULL;
}

/* Whether every byte from offset to the end of the file is zero: what a file system leaves after a
 * power loss when the size was extended but the data never reached the disk. */
static int rest_is_zero(struct trk_recording_reader *r, uint64_t offset)
{
    uint8_t chunk[4096];
    if (fseeko(r->file, (off_t)offset, SEEK_SET) != 0)
        return 0;
    for (uint64_t left = r->file_size - offset; left > 0;) {
        size_t n = left < sizeof chunk ? (size_t)left : sizeof chunk;
        if (fread(chunk, 1, n, r->file) != n)
            return 0;
        for (size_t i = 0; i < n; ++i)
            if (chunk[i])
                return 0;
        left -= n;
    }
    return 1;
}

static int end_torn(struct trk_recording_reader *r)
{
    r->torn_tail = 1;
    r->torn_bytes = r->file_size - r->offset;
    r->offset = r->file_size;
    return 0;
}

int trk_recording_next(struct trk_recording_reader *r, int64_t *host_time_ns, uint8_t *buf, size_t cap,
                       size_t *length, struct hl_error *err)
{
    if (r->offset >= r->file_size)
        return 0;
    uint64_t at = r->offset, left = r->file_size - at;
    if (left < 4)
        return end_torn(r); /* not even a length field: a write cut short */
    if (read_at(r, at, r->buf, 4) != 0)
        return hl_fail(err, "%s: byte %llu: read failed", r->path, (unsigned long long)at);
    uint32_t n = hl_le_get_u32(r->buf + R_LENGTH);
    /* Checked before anything else is read: a corrupt length never sizes a read or an allocation. */
    if (n == 0 || n > TRK_RECORDING_MAX_REPORT) {
        if (rest_is_zero(r, at))
            return end_torn(r);
        return hl_fail(err, "%s: byte %llu: record length %u outside 1..%d (corrupt record)", r->path,
                       (unsigned long long)at, n, TRK_RECORDING_MAX_REPORT);
    }
    uint64_t size = TRK_RECORDING_RECORD_OVERHEAD + (uint64_t)n;
    if (size > left)
        return end_torn(r); /* the last record is incomplete: the writer died during its write */
    if (read_at(r, at, r->buf, (size_t)size) != 0)
        return hl_fail(err, "%s: byte %llu: read failed", r->path, (unsigned long long)at);
    if (hl_le_get_u32(r->buf + R_REPORT + n) != trk_crc32(0, r->buf, R_REPORT + n)) {
        /* A bad last record (it reaches the end of the file), or a bad record followed only by
         * zeros, is what an interrupted write leaves; anywhere else it is damage to report. */
        if (size == left || rest_is_zero(r, at))
            return end_torn(r);
        return hl_fail(err, "%s: byte %llu: record CRC mismatch (corrupt record of %u bytes)", r->path,
                       (unsigned long long)at, n);
    }
    if (n > cap)
        return hl_fail(err, "%s: byte %llu: record of %u bytes does not fit a %zu-byte buffer", r->path,
                       (unsigned long long)at, n, cap);
    memcpy(buf, r->buf + R_REPORT, n);
    *length = n;
    *host_time_ns = get_i64(r->buf + R_TIME);
    r->offset = at + size;
    ++r->records;
    return 1;
}
