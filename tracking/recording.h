/* tracking/recording.h: raw recordings — the file format, its writer and its reader. Part of the
 * tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_RECORDING_H
#define HMDLOD_TRACKING_RECORDING_H

#include <stdio.h>

#include "base/base.h"
#include "tracking/reports.h"

/* Raw recordings (docs/raw-recording.md): a versioned, append-only file of the reports exactly as
 * received, each with its host receive time and a CRC-32, so a session can be replayed through the
 * same parser and fusion, or through a better one later. Little-endian throughout.
 *   header (104 B): "HMDLRAW1", u16 version, u16 header size, u16 kind, u16 vid, u16 pid, u16 0,
 *                   i64 host start ns (CLOCK_MONOTONIC), i64 wall start ns (Unix), char name[64],
 *                   u32 CRC-32 of the 100 bytes before it
 *   record (16 + n B): u32 n, i64 host receive ns, n report bytes, u32 CRC-32 of the 12 + n before it */
#define TRK_RECORDING_MAGIC "HMDLRAW1"
#define TRK_RECORDING_VERSION 1
#define TRK_RECORDING_HEADER_SIZE 104
#define TRK_RECORDING_NAME_SIZE 64       /* bytes in the file, NUL-padded; longer names are cut */
#define TRK_RECORDING_RECORD_OVERHEAD 16 /* length + time + CRC */
#define TRK_RECORDING_MAX_REPORT 1024    /* largest report a record may hold (HID: ≤ 64 B in practice) */

/* CRC-32 (IEEE 802.3, reflected 0xEDB88320, as zlib's crc32): start with crc = 0. */
uint32_t trk_crc32(uint32_t crc, const void *data, size_t length);

/* Writer. create writes the header (host start = now) to a fresh file beside path and renames it over
 * path (base.h's hl_out: a symlink at path is replaced, not followed). NULL with err on failure (no
 * file left behind, and whatever was at path kept). append writes one record with one write() from a buffer in the
 * writer (no allocation per record): after a kill at most the last record is torn. Data reach the
 * kernel at each append (no user-space buffer), so they survive the process dying; surviving power
 * loss needs close with sync_to_disk (fsync). length 1..TRK_RECORDING_MAX_REPORT. After a failed
 * write (disk full) the file is cut back to its last whole record and the writer refuses further
 * appends. close returns 0, or −1 if anything failed (the file is
 * closed and freed either way). */
struct trk_recording;
struct trk_recording *trk_recording_create(const char *path, enum trk_device_kind kind, uint16_t vid, uint16_t pid,
                                           const char *name, struct hl_error *err);
int trk_recording_append(struct trk_recording *rec, int64_t host_time_ns, const uint8_t *report, size_t length,
                         struct hl_error *err);
uint64_t trk_recording_records(const struct trk_recording *rec); /* appended so far */
int trk_recording_close(struct trk_recording *rec, int sync_to_disk, struct hl_error *err);

/* Reader. open checks the header (magic, version, header CRC, kind); NULL with "path: byte N:
 * reason". next returns 1 with one record (report copied into buf, cap ≥ its length), 0 at the end,
 * −1 with "path: byte N: reason" for a corrupt record in the middle. A torn tail — an incomplete last
 * record, or a last record (or zero-filled rest of the file) failing its length or CRC check — ends
 * the file normally: next returns 0 and sets torn_tail and torn_bytes. Lengths are checked against
 * TRK_RECORDING_MAX_REPORT and the file before anything is read; the reader allocates only itself. */
struct trk_recording_info {
    unsigned version;
    enum trk_device_kind kind;
    uint16_t vid, pid;
    char name[TRK_RECORDING_NAME_SIZE + 1];
    int64_t host_start_ns, wall_start_unix_ns;
};
struct trk_recording_reader {
    struct trk_recording_info info;
    uint64_t file_size, offset;  /* offset: next record */
    uint64_t records;            /* complete records returned */
    int torn_tail;               /* 1 when the end was a torn record */
    uint64_t torn_bytes;         /* bytes ignored at the end */
    FILE *file;
    char *path;
    uint8_t buf[TRK_RECORDING_RECORD_OVERHEAD + TRK_RECORDING_MAX_REPORT];
};
struct trk_recording_reader *trk_recording_open(const char *path, struct hl_error *err);
int trk_recording_next(struct trk_recording_reader *r, int64_t *host_time_ns, uint8_t *buf, size_t cap,
                       size_t *length, struct hl_error *err);
void trk_recording_reader_close(struct trk_recording_reader *r);

#endif
