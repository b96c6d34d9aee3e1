/* tests/fuzz/replay_main.c: the driver a fuzz target gets in a normal (gcc) build, in place of
 * libFuzzer's: runs LLVMFuzzerTestOneInput once on each file named, and on every file in each folder
 * named (the seed corpus and the regression inputs), so ctest replays them without clang. A target
 * that aborts fails the test; exit 0 when every input ran, 1 when one could not be read or none
 * was found. Absent paths are skipped (a target with no finding yet has no regression folder). */
#include "fuzz_util.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        perror(path);
        return -1;
    }
    size_t cap = 4096, n = 0;
    uint8_t *buf = malloc(cap);
    size_t got;
    while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            uint8_t *grown = realloc(buf, cap * 2);
            if (!grown) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = grown, cap *= 2;
        }
    }
    int bad = ferror(f) || !buf;
    fclose(f);
    if (bad) {
        fprintf(stderr, "%s: cannot read\n", path);
        free(buf);
        return -1;
    }
    /* libFuzzer hands the target a buffer of exactly the input's size: so do we (ASan sees overreads) */
    uint8_t *exact = malloc(n ? n : 1);
    if (!exact) {
        free(buf);
        return -1;
    }
    memcpy(exact, buf, n);
    free(buf);
    LLVMFuzzerTestOneInput(exact, n);
    free(exact);
    return 0;
}

static int cmp_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Every regular file of dir, in name order (a failure names the same input on every machine). */
static int run_dir(const char *dir, int *ran)
{
    DIR *d = opendir(dir);
    if (!d) {
        perror(dir);
        return -1;
    }
    char **names = NULL;
    size_t count = 0, cap = 0;
    struct dirent *e;
    int rc = 0;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        if (count == cap) {
            cap = cap ? cap * 2 : 64;
            char **grown = realloc(names, cap * sizeof *names);
            if (!grown) {
                rc = -1;
                break;
            }
            names = grown;
        }
        names[count] = strdup(e->d_name);
        if (!names[count]) {
            rc = -1;
            break;
        }
        ++count;
    }
    closedir(d);
    if (count)
        qsort(names, count, sizeof *names, cmp_names);
    char path[8192];
    for (size_t i = 0; i < count; ++i) {
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        if (rc == 0 && stat(path, &st) == 0 && S_ISREG(st.st_mode)) {
            if (run_file(path) != 0)
                rc = -1;
            else
                ++*ran;
        }
        free(names[i]);
    }
    free(names);
    return rc;
}

int main(int argc, char **argv)
{
    int ran = 0, rc = 0;
    for (int i = 1; i < argc; ++i) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            /* an absent regression folder is normal (no finding yet for this target) */
            continue;
        }
        if (S_ISDIR(st.st_mode)) {
            if (run_dir(argv[i], &ran) != 0)
                rc = 1;
        } else if (run_file(argv[i]) != 0) {
            rc = 1;
        } else {
            ++ran;
        }
    }
    printf("%s: %d inputs replayed\n", argc > 0 ? argv[0] : "replay", ran);
    if (ran == 0) { /* a corpus folder gone missing must not pass as "nothing failed" */
        fprintf(stderr, "no input found\n");
        return 1;
    }
    return rc;
}
