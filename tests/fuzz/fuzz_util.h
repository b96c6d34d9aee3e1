/* tests/fuzz/fuzz_util.h: what the fuzz targets share — a per-process scratch folder for the loaders
 * that take a path, a reader of length-prefixed chunks for the report streams, and a check that
 * aborts (a finding) when a parser's promise is broken. Built into every target, with libFuzzer's
 * driver or tests/fuzz/replay_main.c. */
#ifndef HMDLOD_FUZZ_UTIL_H
#define HMDLOD_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* "DIR/name" in a folder made once per process (mkdtemp under $TMPDIR, removed at exit with
 * everything fuzz_write_file put in it). The pointer stays valid until the next call. */
const char *fuzz_temp_path(const char *name);
/* Writes the bytes to fuzz_temp_path(name) (truncating) and returns that path; aborts if it cannot:
 * a scratch folder that does not work is no finding of the code under test. */
const char *fuzz_write_file(const char *name, const uint8_t *data, size_t size);

/* Cuts the next chunk off *data: one length byte, then up to that many bytes (fewer at the end).
 * Returns 0 with *chunk / *length set, or −1 when nothing is left. */
int fuzz_next_chunk(const uint8_t **data, size_t *size, const uint8_t **chunk, size_t *length);
/* Takes n bytes as a little-endian unsigned number (missing bytes read 0). */
uint64_t fuzz_take_le(const uint8_t **data, size_t *size, size_t n);

/* A broken promise of the code under test: prints what and where, then aborts (libFuzzer keeps
 * the input as a crash artifact; the replay driver fails). */
#define FUZZ_CHECK(cond, what)                                                                                       \
    do {                                                                                                             \
        if (!(cond))                                                                                                 \
            fuzz_fail(__FILE__, __LINE__, (what));                                                                   \
    } while (0)
void fuzz_fail(const char *file, int line, const char *what)
#if defined(__GNUC__)
    __attribute__((noreturn))
#endif
    ;

#endif
