/* Fuzz target: raw tracker recordings (tracking/recording.c's reader, docs/raw-recording.md) as
 * files, then the same file as a trace (rpl_trace_from_recording: every record through the parser
 * and fusion). With FUZZ_RECORDING_REPAIR (fuzz_recording_repair) the input is first made into a
 * file whose header and record checksums and lengths are right, so the fuzzer gets past them to the
 * records and the reports in them; the plain target keeps the bytes as they are (the checks). */
#include "fuzz_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "replay/replay.h"
#include "tracking/recording.h"

#ifdef FUZZ_RECORDING_REPAIR
static void put_le(uint8_t *p, uint64_t v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        p[i] = (uint8_t)(v >> (8 * i));
}

/* Header: the magic, version 1, header size, then kind (the input's, mod 8: one past the last kind
 * is kept reachable), vid, pid, 0, both start times and the name (a length byte, ≤ 64 bytes) from the input, CRC fixed. Records:
 * a length byte (0 → a 64-byte report, the common size), 8 bytes of host time, the report, CRC
 * fixed; a short last record stays short (a torn tail). Returns the file's size. */
static size_t repair(const uint8_t *data, size_t size, uint8_t *out, size_t cap)
{
    uint8_t h[TRK_RECORDING_HEADER_SIZE] = {0};
    memcpy(h, TRK_RECORDING_MAGIC, 8);
    put_le(h + 8, TRK_RECORDING_VERSION, 2);
    put_le(h + 10, TRK_RECORDING_HEADER_SIZE, 2);
    put_le(h + 12, fuzz_take_le(&data, &size, 1) % 8, 2);
    put_le(h + 14, fuzz_take_le(&data, &size, 2), 2);
    put_le(h + 16, fuzz_take_le(&data, &size, 2), 2);
    put_le(h + 20, fuzz_take_le(&data, &size, 8), 8);
    put_le(h + 28, fuzz_take_le(&data, &size, 8), 8);
    size_t name = fuzz_take_le(&data, &size, 1) % (TRK_RECORDING_NAME_SIZE + 1);
    if (name > size)
        name = size;
    memcpy(h + 36, data, name);
    data += name, size -= name;
    put_le(h + 100, trk_crc32(0, h, 100), 4);
    memcpy(out, h, sizeof h);
    size_t n = sizeof h;
    while (size > 0 && n + TRK_RECORDING_RECORD_OVERHEAD + 256 <= cap) {
        size_t len = fuzz_take_le(&data, &size, 1);
        if (len == 0)
            len = 64;
        int64_t host = (int64_t)fuzz_take_le(&data, &size, 8);
        size_t have = len < size ? len : size;
        uint8_t *r = out + n;
        put_le(r, len, 4);
        put_le(r + 4, (uint64_t)host, 8);
        memcpy(r + 12, data, have);
        data += have, size -= have;
        if (have < len) { /* torn: the bytes there are, no CRC */
            n += 12 + have;
            break;
        }
        put_le(r + 12 + len, trk_crc32(0, r, 12 + len), 4);
        n += TRK_RECORDING_RECORD_OVERHEAD + len;
    }
    return n;
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
#ifdef FUZZ_RECORDING_REPAIR
    size_t cap = TRK_RECORDING_HEADER_SIZE + 2 * size + 1024;
    uint8_t *file = malloc(cap);
    if (!file)
        return 0;
    size_t n = repair(data, size, file, cap);
    const char *path = fuzz_write_file("fuzz.hmdlraw", file, n);
    free(file);
#else
    const char *path = fuzz_write_file("fuzz.hmdlraw", data, size);
#endif
    struct hl_error err;
    struct trk_recording_reader *r = trk_recording_open(path, &err);
    if (r) {
        uint8_t buf[TRK_RECORDING_MAX_REPORT];
        int64_t host;
        size_t length;
        int rc;
        uint64_t records = 0;
        while ((rc = trk_recording_next(r, &host, buf, sizeof buf, &length, &err)) == 1) {
            FUZZ_CHECK(length >= 1 && length <= TRK_RECORDING_MAX_REPORT, "record length out of range");
            ++records;
        }
        FUZZ_CHECK(records == r->records, "records returned differ from the reader's count");
        FUZZ_CHECK(r->offset <= r->file_size, "reader offset past the end of the file");
        trk_recording_reader_close(r);
    }
    struct rpl_trace t;
    if (rpl_trace_from_recording(path, &t, &err) == 0) {
        for (size_t i = 0; i < t.count; ++i) {
            const hl_quatd *q = &t.orientation[i];
            FUZZ_CHECK(isfinite(t.time_s[i]) && isfinite(q->w + q->x + q->y + q->z), "recording trace not finite");
            FUZZ_CHECK(i == 0 || t.time_s[i] > t.time_s[i - 1], "recording trace times not increasing");
        }
        rpl_trace_free(&t);
    }
    return 0;
}
