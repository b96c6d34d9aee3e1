#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int tu_failures;
int tu_checks;

void tu_check_near(double actual, double expected, double tol, const char *what, const char *file, int line)
{
    ++tu_checks;
    if (!(fabs(actual - expected) <= tol)) {
        ++tu_failures;
        fprintf(stderr, "%s:%d: %s = %.9g, expected %.9g ± %.3g\n", file, line, what, actual, expected, tol);
    }
}

double tu_time_scale(void)
{
    const char *v = getenv("HMDLOD_TEST_TIME_SCALE");
    char *end;
    double f = v ? strtod(v, &end) : 1.0;
    return v && end != v && *end == '\0' && f >= 1.0 && f <= 1000.0 ? f : 1.0;
}

const char *tu_shared_path(const char *relative)
{
    static char path[4096];
    const char *root = getenv("HMDLOD_SHARED");
    snprintf(path, sizeof path, "%s/%s", root && *root ? root : "../shared", relative);
    if (access(path, R_OK) != 0) {
        printf("skip: %s is absent (set HMDLOD_SHARED to the shared data folder)\n", path);
        return NULL;
    }
    return path;
}

const char *tu_source_path(const char *relative)
{
    static char path[4096];
    const char *src = getenv("HMDLOD_SOURCE");
    if (src && *src) {
        snprintf(path, sizeof path, "%s/%s", src, relative);
    } else { /* run by hand: this file's folder is tests/ (CMake passes full paths) */
        snprintf(path, sizeof path, "%s", __FILE__);
        char *slash = strrchr(path, '/');
        snprintf(slash ? slash + 1 : path, sizeof path - (size_t)(slash ? slash + 1 - path : 0), "../%s", relative);
    }
    return path;
}

char *tu_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0)
        buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    if (buf) {
        buf[n] = '\0';
        *size = (size_t)n;
    }
    return buf;
}

int tu_finish(const char *suite)
{
    printf("%s: %d checks, %d failed\n", suite, tu_checks, tu_failures);
    return tu_failures ? 1 : 0;
}

const char *tu_csv_cell(const char *csv, long row, const char *name)
{
    char key[96];
    snprintf(key, sizeof key, ",%s,", name);
    const char *at = strstr(csv, key), *eol = strchr(csv, '\n');
    if (!at || !eol || at > eol)
        return NULL;
    int column = 0; /* commas before the cell */
    for (const char *c = csv; c <= at; ++c)
        column += *c == ',';
    const char *line = csv;
    for (long k = -1; k < row && line; ++k)
        line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL;
    for (int commas = 0; line && *line && *line != '\n' && commas < column; ++line)
        commas += *line == ',';
    return line && *line ? line : NULL;
}
