/* Where the soak's resident memory lies (soak_internal.h: bch_soak_memory_read). RSS alone cannot
 * tell a leak from allocator fragmentation from a driver's mappings or library pages faulted in late;
 * the split by mapping kind and malloc's own in-use and free counts can (docs/bench.md "Soak"). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <malloc.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench/soak_internal.h"

/* Resident set in KiB from /proc/self/statm (pages × page size); −1 when unreadable. */
static long statm_rss_kib(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long size = 0, resident = -1;
    if (!f)
        return -1;
    if (fscanf(f, "%ld %ld", &size, &resident) != 2)
        resident = -1;
    fclose(f);
    return resident < 0 ? -1 : resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/* Open file descriptors: entries of /proc/self/fd less the one opendir holds; −1 when unreadable. */
static long open_fds(void)
{
    DIR *d = opendir("/proc/self/fd");
    if (!d)
        return -1;
    long n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += e->d_name[0] != '.';
    closedir(d);
    return n - 1;
}

/* A smaps header line: "start-end perms offset dev inode [pathname]". Its pathname, or "" when the
 * mapping is anonymous; NULL when the line is not a header. */
static const char *smaps_header_path(const char *line)
{
    unsigned long lo, hi, offset, inode;
    char perms[8], dev[16];
    int used = 0;
    if (sscanf(line, "%lx-%lx %7s %lx %15s %lu %n", &lo, &hi, perms, &offset, dev, &inode, &used) < 6 || used == 0)
        return NULL;
    return line + used;
}

enum smaps_kind { KIND_HEAP, KIND_ANON, KIND_FILE, KIND_OTHER };

static enum smaps_kind smaps_kind_of(const char *path)
{
    if (strncmp(path, "[heap]", 6) == 0)
        return KIND_HEAP;
    if (path[0] == '\0' || path[0] == '\n')
        return KIND_ANON;
    return path[0] == '/' ? KIND_FILE : KIND_OTHER; /* [stack], [vdso], … */
}

/* Sums Rss of /proc/self/smaps by mapping kind and counts the mappings; 0, or −1 when unreadable. A
 * line longer than the buffer (a long path) arrives in pieces: only pieces that start a line are
 * parsed. */
static int read_smaps(struct bch_soak_memory *m)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f)
        return -1;
    char line[512];
    int at_line_start = 1;
    enum smaps_kind kind = KIND_OTHER;
    long kib[4] = {0, 0, 0, 0}, maps = 0;
    while (fgets(line, sizeof line, f)) {
        int starts = at_line_start;
        at_line_start = strchr(line, '\n') != NULL;
        if (!starts)
            continue;
        long v;
        const char *path;
        /* field lines start with a capital ("Rss:", "Pss:", "VmFlags:"); headers with the address, in
         * lower-case hex */
        if (strncmp(line, "Rss:", 4) == 0) {
            if (sscanf(line + 4, "%ld", &v) == 1)
                kib[kind] += v;
        } else if (!(line[0] >= 'A' && line[0] <= 'Z') && (path = smaps_header_path(line))) {
            kind = smaps_kind_of(path), maps++;
        }
    }
    fclose(f);
    m->heap_map_kib = kib[KIND_HEAP], m->anon_map_kib = kib[KIND_ANON], m->file_map_kib = kib[KIND_FILE];
    m->mappings = maps;
    return 0;
}

void bch_soak_memory_read(struct bch_soak_memory *m, int with_smaps)
{
    m->rss_kib = statm_rss_kib();
    m->fds = open_fds();
    m->heap_in_use_kib = m->heap_free_kib = -1;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
    struct mallinfo2 mi = mallinfo2();
    m->heap_in_use_kib = (long)((mi.uordblks + mi.hblkhd) / 1024);
    m->heap_free_kib = (long)(mi.fordblks / 1024);
#endif
    m->heap_map_kib = m->anon_map_kib = m->file_map_kib = m->mappings = -1;
    if (with_smaps)
        read_smaps(m);
}

double *bch_soak_series_alloc(long n)
{
    if (n < 1 || (unsigned long)n > SIZE_MAX / sizeof(double))
        return NULL;
    double *v = malloc((size_t)n * sizeof *v);
    if (v)
        for (long i = 0; i < n; ++i)
            v[i] = NAN;
    return v;
}
