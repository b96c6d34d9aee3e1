/* Minimal test harness shared by the test programs: CHECK macros that count failures and keep
 * going, tolerance checks that print both values, and the location of ../shared. */
#ifndef HMDLOD_TEST_UTIL_H
#define HMDLOD_TEST_UTIL_H

#include <stddef.h>
#include <stdio.h>

extern int tu_failures;
extern int tu_checks;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        ++tu_checks;                                                                               \
        if (!(cond)) {                                                                             \
            ++tu_failures;                                                                         \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);               \
        }                                                                                          \
    } while (0)

/* |actual − expected| ≤ tol; NaN never passes. */
#define CHECK_NEAR(actual, expected, tol) tu_check_near((actual), (expected), (tol), #actual, __FILE__, __LINE__)
void tu_check_near(double actual, double expected, double tol, const char *what, const char *file, int line);

/* Path of a file under the shared data folder (HMDLOD_SHARED, else ../shared); NULL if absent,
 * after printing "skip: <why>". The returned buffer is static (one at a time). */
const char *tu_shared_path(const char *relative);

/* Path of a file in the source tree (HMDLOD_SOURCE, which ctest sets; else found from this file's
 * own path, for a test run by hand). The returned buffer is static (one at a time). */
const char *tu_source_path(const char *relative);

/* Reads a whole file into a new NUL-terminated buffer (caller frees); NULL if it cannot.
 * *size gets the byte count (the NUL is not counted). */
char *tu_read_file(const char *path, size_t *size);

/* Factor for the wall-clock waits of tests that wait on other threads or processes:
 * HMDLOD_TEST_TIME_SCALE (1 to 1000; scripts/valgrind-tests.sh sets it, memcheck runs code ~20–50×
 * slower), else 1. Bounds only; what a test checks stays the same. */
double tu_time_scale(void);

/* Prints the summary and returns the process exit code (0 pass, 1 fail). */
int tu_finish(const char *suite);
/* The cell of column `name` (found by the header line, not first or last) in data row `row` (0-based)
 * of a CSV text: a pointer to its first character (',' or '\n' when empty), NULL when the column or
 * the row is absent. */
const char *tu_csv_cell(const char *csv, long row, const char *name);

#endif
