/* tests/fuzz/fuzz_util.c: the fuzz targets' scratch folder, chunk reader and check (fuzz_util.h). */
#include "fuzz_util.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char temp_dir[4096];
static char temp_path[4200];

static void remove_temp_dir(void)
{
    DIR *d = opendir(temp_dir);
    if (d) {
        struct dirent *e;
        char path[4400];
        while ((e = readdir(d)) != NULL) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
                continue;
            snprintf(path, sizeof path, "%s/%s", temp_dir, e->d_name);
            remove(path);
        }
        closedir(d);
    }
    rmdir(temp_dir);
}

const char *fuzz_temp_path(const char *name)
{
    if (!temp_dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(temp_dir, sizeof temp_dir, "%s/hmdlod-fuzz-XXXXXX", tmp && *tmp ? tmp : "/tmp");
        if (!mkdtemp(temp_dir)) {
            perror("fuzz: mkdtemp");
            abort();
        }
        atexit(remove_temp_dir);
    }
    if (!name || !*name)
        return temp_dir;
    snprintf(temp_path, sizeof temp_path, "%s/%s", temp_dir, name);
    return temp_path;
}

const char *fuzz_write_file(const char *name, const uint8_t *data, size_t size)
{
    const char *path = fuzz_temp_path(name);
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        perror("fuzz: writing the scratch file");
        abort();
    }
    return path;
}

int fuzz_next_chunk(const uint8_t **data, size_t *size, const uint8_t **chunk, size_t *length)
{
    if (*size == 0)
        return -1;
    size_t want = (*data)[0];
    *data += 1, *size -= 1;
    *length = want < *size ? want : *size;
    *chunk = *data;
    *data += *length, *size -= *length;
    return 0;
}

uint64_t fuzz_take_le(const uint8_t **data, size_t *size, size_t n)
{
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i) {
        if (*size) {
            v |= (uint64_t)(*data)[0] << (8 * i);
            *data += 1, *size -= 1;
        }
    }
    return v;
}

void fuzz_fail(const char *file, int line, const char *what)
{
    fprintf(stderr, "%s:%d: fuzz check failed: %s\n", file, line, what);
    abort();
}
