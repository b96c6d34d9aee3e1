/* .lod files: round trip bit for bit (NaN payloads too), every truncated prefix and every
 * single-byte corruption refused with the path, wrong version and magic, FIFOs, directories and
 * missing files refused without blocking, well-checksummed nonsense refused at the right byte, and
 * the writer leaving nothing behind when it fails. The CRC here is a separate bitwise
 * implementation, checked against the standard check value. */
#define _DEFAULT_SOURCE
#include "scene/scene_internal.h"
#include "test_util.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[] = "/tmp/hmdlod-test-lodfile-XXXXXX";

static const char *tmp_path(const char *name)
{
    static char buf[2][256];
    static int which;
    which ^= 1;
    snprintf(buf[which], sizeof buf[which], "%s/%s", dir, name);
    return buf[which];
}

/* Bitwise CRC-32 (no table): the definition, independent of scene's table-driven one. */
static uint32_t crc32_bitwise(const unsigned char *p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return ~c;
}

static uint32_t rd32(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }
static uint64_t rd64(const unsigned char *p) { return rd32(p) | (uint64_t)rd32(p + 4) << 32; }
static void wr32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        p[i] = (unsigned char)(v >> (8 * i));
}
static void wr64(unsigned char *p, uint64_t v)
{
    for (int i = 0; i < 8; ++i)
        p[i] = (unsigned char)(v >> (8 * i));
}
static void reseal(unsigned char *b, size_t n) { wr32(b + n - 4, crc32_bitwise(b, n - 4)); }

static int write_bytes(const char *path, const unsigned char *b, size_t n)
{
    /* A new file each time: truncating one in place makes ext4 flush it on close (auto_da_alloc),
     * which turns 12 000 small writes into minutes on a busy disk. */
    unlink(path);
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t w = fwrite(b, 1, n, f);
    return fclose(f) == 0 && w == n ? 0 : -1;
}

static double bumpy(hl_vec3d d) { return 1.0 + 0.2 * d.x * d.y; }

static uint64_t nan_with_payload = 0x7ff8dead0000beefull;

static void make_set(struct scn_lodset *set)
{
    *set = (struct scn_lodset){0};
    scn_mesh_add_sphere(&set->levels[0], 0.5, 4, 6, bumpy); /* 48 triangles */
    scn_mesh_add_box(&set->levels[1], hl_v3(0.1, 0, 0), hl_v3(0.5, 0.4, 0.5), hl_q_identity()); /* 12 */
    struct scn_mesh *t = &set->levels[2]; /* a tetrahedron: 4 */
    for (int i = 0; i < 4; ++i)
        scn_mesh_add_vertex(t, hl_v3(i == 1, i == 2, i == 3), hl_v3_normalize(hl_v3(i == 1, i == 2, i == 3 || i == 0)));
    scn_mesh_add_triangle(t, 0, 2, 1), scn_mesh_add_triangle(t, 0, 1, 3);
    scn_mesh_add_triangle(t, 0, 3, 2), scn_mesh_add_triangle(t, 1, 2, 3);
    set->level_count = 3;
    double nanp;
    memcpy(&nanp, &nan_with_payload, 8);
    for (int l = 0; l < 3; ++l) {
        set->error_m[l] = l * 0.0123;
        set->error_rel[l] = l * 0.0246;
        set->freq[l] = (struct scn_level_freq){l == 0 ? INFINITY : NAN, l == 0 ? INFINITY : nanp, l == 0 ? INFINITY : 40.0 / l};
    }
    set->center_m[0] = 0.01, set->center_m[1] = -0.02, set->center_m[2] = 0.3;
    set->radius_m = 0.6123456789;
    for (int k = 0; k < 3; ++k)
        set->aabb_min_m[k] = -0.5 - 0.1 * k, set->aabb_max_m[k] = 0.5 + 0.01 * k;
    set->source_hash = scn_mesh_hash(&set->levels[0]);
    snprintf(set->simplifier, sizeof set->simplifier, "meshopt");
    set->analysis_views = 26;
    set->analysis_size_px = 256;
}

static int is_zero(const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; ++i)
        if (b[i])
            return 0;
    return 1;
}

static int same_bits(const void *a, const void *b, size_t n) { return memcmp(a, b, n) == 0; }

static void test_crc(void)
{
    CHECK(crc32_bitwise((const unsigned char *)"123456789", 9) == 0xCBF43926u); /* the CRC-32 check value */
    CHECK(scn_crc32("123456789", 9) == 0xCBF43926u);
    CHECK(scn_crc32("", 0) == 0);
}

static void test_round_trip(void)
{
    struct scn_lodset set, back;
    struct hl_error err = {""};
    make_set(&set);
    const char *p = tmp_path("a.lod");
    CHECK(scn_lodfile_write(p, &set, &err) == 0);
    if (err.msg[0])
        printf("  %s\n", err.msg);
    memset(&back, 0xAB, sizeof back);
    CHECK(scn_lodfile_read(p, &back, &err) == 0);
    CHECK(back.level_count == set.level_count);
    for (int l = 0; l < set.level_count; ++l) {
        const struct scn_mesh *a = &set.levels[l], *b = &back.levels[l];
        CHECK(a->vertex_count == b->vertex_count && a->index_count == b->index_count);
        CHECK(same_bits(a->positions, b->positions, 12 * (size_t)a->vertex_count));
        CHECK(same_bits(a->normals, b->normals, 12 * (size_t)a->vertex_count));
        CHECK(same_bits(a->indices, b->indices, 4 * (size_t)a->index_count));
        CHECK(b->failed == 0);
    }
    CHECK(same_bits(set.error_m, back.error_m, sizeof set.error_m));
    CHECK(same_bits(set.error_rel, back.error_rel, sizeof set.error_rel));
    CHECK(same_bits(set.freq, back.freq, sizeof set.freq)); /* NaN and its payload, +Inf */
    uint64_t bits;
    memcpy(&bits, &back.freq[1].long_cpdiam, 8);
    CHECK(bits == nan_with_payload);
    CHECK(isnan(back.freq[2].narrow_cpdiam) && isinf(back.freq[0].geometric_cpdiam));
    CHECK(same_bits(set.center_m, back.center_m, sizeof set.center_m));
    CHECK(same_bits(&set.radius_m, &back.radius_m, sizeof set.radius_m));
    CHECK(same_bits(set.aabb_min_m, back.aabb_min_m, sizeof set.aabb_min_m));
    CHECK(same_bits(set.aabb_max_m, back.aabb_max_m, sizeof set.aabb_max_m));
    CHECK(back.source_hash == set.source_hash);
    CHECK(same_bits(set.simplifier, back.simplifier, sizeof set.simplifier));
    CHECK(back.analysis_views == 26 && back.analysis_size_px == 256);
    CHECK(scn_mesh_hash(&back.levels[0]) == set.source_hash);
    /* The same set writes the same bytes; the arrays are 16-byte aligned; the CRC is the last 4. */
    size_t n1 = 0, n2 = 0;
    unsigned char *b1 = (unsigned char *)tu_read_file(p, &n1);
    CHECK(scn_lodfile_write(tmp_path("b.lod"), &back, &err) == 0);
    unsigned char *b2 = (unsigned char *)tu_read_file(tmp_path("b.lod"), &n2);
    CHECK(b1 && b2 && n1 == n2 && memcmp(b1, b2, n1) == 0);
    if (b1) {
        CHECK(memcmp(b1, "HMDLOD\0\1", 8) == 0 && rd32(b1 + 8) == 1 && rd64(b1 + 24) == n1);
        for (int l = 0; l < 3; ++l)
            for (int k = 0; k < 3; ++k)
                CHECK(rd64(b1 + 144 + 72 * l + 8 + 8 * k) % 16 == 0);
        CHECK(rd32(b1 + n1 - 4) == crc32_bitwise(b1, n1 - 4));
        printf("  3-level file: %zu bytes\n", n1);
    }
    free(b1), free(b2);
    struct stat st;
    CHECK(stat(p, &st) == 0 && (st.st_mode & 0777) == 0644);
    unlink(tmp_path("b.lod"));
    scn_lodset_free(&back);
    scn_lodset_free(&set);
}

/* Reads path expecting a refusal whose message names the path (and `needle` when given); *out zeroed. */
static int refused(const char *path, const char *needle)
{
    struct scn_lodset out;
    memset(&out, 0x5A, sizeof out);
    struct hl_error err = {""};
    int ok = scn_lodfile_read(path, &out, &err) < 0 && strstr(err.msg, path) != NULL &&
             (!needle || strstr(err.msg, needle) != NULL) && is_zero(&out, sizeof out);
    if (!ok)
        fprintf(stderr, "  unexpected: \"%s\" (wanted \"%s\")\n", err.msg, needle ? needle : "");
    return ok;
}

static void test_damage(void)
{
    size_t n = 0;
    unsigned char *good = (unsigned char *)tu_read_file(tmp_path("a.lod"), &n);
    CHECK(good != NULL);
    if (!good)
        return;
    unsigned char *b = malloc(n);
    const char *p = tmp_path("damaged.lod");
    int bad = 0;
    for (size_t len = 0; len < n; ++len) { /* every truncated prefix */
        CHECK(write_bytes(p, good, len) == 0);
        bad += !refused(p, "byte ");
    }
    CHECK(bad == 0);
    static const unsigned char patterns[] = {0x01, 0x80, 0xFF, 0x5A};
    bad = 0;
    int crc_caught = 0;
    for (size_t i = 0; i < n; ++i) /* every single-byte corruption */
        for (size_t k = 0; k < sizeof patterns; ++k) {
            memcpy(b, good, n);
            b[i] ^= patterns[k];
            CHECK(write_bytes(p, b, n) == 0);
            bad += !refused(p, "byte ");
            struct hl_error err = {""};
            struct scn_lodset out;
            if (scn_lodfile_read(p, &out, &err) < 0 && strstr(err.msg, "CRC-32 mismatch"))
                ++crc_caught;
        }
    printf("  %zu prefixes and %zu corruptions refused (%d by the CRC)\n", n, 4 * n, crc_caught);
    CHECK(bad == 0);
    CHECK(crc_caught > (int)(3 * n)); /* all but the header's structural fields reach the CRC */
    /* Appended bytes. */
    unsigned char *longer = calloc(1, n + 1);
    memcpy(longer, good, n);
    CHECK(write_bytes(p, longer, n + 1) == 0);
    CHECK(refused(p, "byte 24: "));
    free(longer);
    /* A newer version, version 0, bad magic, unknown flags (CRC resealed). */
    memcpy(b, good, n), wr32(b + 8, 3), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 8: written by a newer hmdlod: version 3, this reads 2"));
    /* Version 2 with version 1's header size: refused at the header size, not read as either. */
    memcpy(b, good, n), wr32(b + 8, 2), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 16: header size 144, version 2 has 160"));
    memcpy(b, good, n), wr32(b + 8, 0), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 8: "));
    memcpy(b, good, n), memcpy(b, "HMDLOE", 6), write_bytes(p, b, n);
    CHECK(refused(p, "byte 0: bad magic"));
    CHECK(write_bytes(p, (const unsigned char *)"v 0 0 0\n", 8) == 0);
    CHECK(refused(p, "byte 0: bad magic"));
    memcpy(b, good, n), wr32(b + 12, 4), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 12: unknown flags"));
    free(b);
    free(good);
    unlink(p);
}

/* Valid CRC, wrong meaning: each patch is resealed, and the refusal names the patched field's byte. */
static void test_nonsense(void)
{
    size_t n = 0;
    unsigned char *good = (unsigned char *)tu_read_file(tmp_path("a.lod"), &n);
    CHECK(good != NULL);
    if (!good)
        return;
    unsigned char *b = malloc(n);
    const char *p = tmp_path("nonsense.lod");
    char want[128];
    const size_t rec0 = 144, rec1 = 144 + 72;
    uint64_t idx0 = rd64(good + rec0 + 24), pos1 = rd64(good + rec1 + 8), nrm0 = rd64(good + rec0 + 16);
    uint32_t tris0 = rd32(good + rec0);

    memcpy(b, good, n), wr32(b + idx0 + 4 * 5, 9999), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %llu: level 0: triangle 1: index 9999", (unsigned long long)(idx0 + 20));
    CHECK(refused(p, want));

    memcpy(b, good, n), wr32(b + pos1 + 4 * 7, 0x7fc00000u), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %llu: level 1: vertex 2: position", (unsigned long long)(pos1 + 28));
    CHECK(refused(p, want));

    memcpy(b, good, n), wr32(b + nrm0, 0x7f800000u), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %llu: level 0: vertex 0: normal", (unsigned long long)nrm0);
    CHECK(refused(p, want));

    memcpy(b, good, n), wr32(b + rec1, tris0 + 1), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %zu: level 1 has %u triangles, not fewer", rec1, tris0 + 1);
    CHECK(refused(p, want));

    double v = -0.5;
    uint64_t bits;
    memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + rec1 + 32, bits), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %zu: level 1: error", rec1 + 32);
    CHECK(refused(p, want));

    v = INFINITY, memcpy(&bits, &v, 8); /* +Inf only at level 0 */
    memcpy(b, good, n), wr64(b + rec1 + 64, bits), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %zu: level 1: frequency inf", rec1 + 64);
    CHECK(refused(p, want));

    v = 0, memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + rec0 + 48, bits), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %zu: level 0: frequency 0", rec0 + 48);
    CHECK(refused(p, want));

    memcpy(b, good, n), wr32(b + 20, 0), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 20: 0 levels"));
    memcpy(b, good, n), wr32(b + 20, 9), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 20: 9 levels"));

    memcpy(b, good, n), wr32(b + rec1 + 4, rd32(good + rec1 + 4) + 1), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %zu: level 1: normals at byte", rec1 + 16); /* layout no longer fits */
    CHECK(refused(p, want));

    memcpy(b, good, n), wr32(b + rec1 + 4, 0xFFFFFFF0u), reseal(b, n), write_bytes(p, b, n); /* huge count */
    CHECK(refused(p, "level 1: "));

    memcpy(b, good, n), wr64(b + rec0 + 8, rd64(good + rec0 + 8) + 16), reseal(b, n), write_bytes(p, b, n);
    snprintf(want, sizeof want, "byte %zu: level 0: positions at byte", rec0 + 8);
    CHECK(refused(p, want));

    memcpy(b, good, n), memset(b + 32, 'x', 16), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 32: simplifier name"));

    v = NAN, memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + 80, bits), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 80: bounds"));

    memcpy(b, good, n), wr64(b + 24, 100), reseal(b, n), write_bytes(p, b, n);
    CHECK(refused(p, "byte 24: ")); /* declared size is checked against the file before the CRC */
    free(b);
    free(good);
    unlink(p);
}

/* Version 2: the lost-contrast spectrum. Written only when the set has one (a.lod, without, stays
 * version 1 and reads back with none); read back bit for bit; every prefix and single-byte
 * corruption refused; nonsense in the new fields refused at their byte. */
static void test_v2(void)
{
    struct scn_lodset set, back;
    struct hl_error err = {""};
    CHECK(scn_lodfile_read(tmp_path("a.lod"), &back, &err) == 0);
    CHECK(back.contrast_band_count == 0 && back.contrast_percentile == 0);
    scn_lodset_free(&back);
    make_set(&set);
    set.contrast_band_count = 7;
    set.contrast_percentile = 99;
    for (int l = 1; l < 3; ++l)
        for (int b = 0; b < 7; ++b)
            set.lost_contrast[l][b] = 0.01 * (b + 1) * l;
    set.lost_contrast[2][3] = NAN; /* no object pixel in that band */
    const char *p = tmp_path("v2.lod");
    CHECK(scn_lodfile_write(p, &set, &err) == 0);
    CHECK(scn_lodfile_read(p, &back, &err) == 0);
    CHECK(back.contrast_band_count == 7 && back.contrast_percentile == 99);
    CHECK(same_bits(set.lost_contrast, back.lost_contrast, sizeof set.lost_contrast));
    CHECK(same_bits(set.freq, back.freq, sizeof set.freq) && back.analysis_views == 26);
    for (int l = 0; l < 3; ++l)
        CHECK(scn_mesh_hash(&back.levels[l]) == scn_mesh_hash(&set.levels[l]));
    scn_lodset_free(&back);
    size_t n = 0;
    unsigned char *good = (unsigned char *)tu_read_file(p, &n);
    CHECK(good && rd32(good + 8) == 2 && rd32(good + 16) == 160 && rd32(good + 144) == 7 && rd32(good + 148) == 0);
    if (!good) {
        scn_lodset_free(&set);
        return;
    }
    for (int l = 0; l < 3; ++l)
        for (int k = 0; k < 3; ++k)
            CHECK(rd64(good + 160 + 168 * l + 8 + 8 * k) % 16 == 0);
    printf("  3-level version 2 file: %zu bytes\n", n);
    unsigned char *b = malloc(n);
    const char *q = tmp_path("v2-damaged.lod");
    int bad = 0;
    for (size_t len = 0; len < n; ++len) {
        CHECK(write_bytes(q, good, len) == 0);
        bad += !refused(q, "byte ");
    }
    static const unsigned char patterns[] = {0x01, 0x80, 0xFF, 0x5A};
    for (size_t i = 0; i < n; ++i)
        for (size_t k = 0; k < sizeof patterns; ++k) {
            memcpy(b, good, n);
            b[i] ^= patterns[k];
            CHECK(write_bytes(q, b, n) == 0);
            bad += !refused(q, "byte ");
        }
    CHECK(bad == 0);
    char want[160];
    const size_t rec0 = 160, rec1 = 160 + 168, band0 = 72;
    memcpy(b, good, n), wr32(b + 144, 13), reseal(b, n), write_bytes(q, b, n);
    CHECK(refused(q, "byte 144: 13 contrast bands"));
    memcpy(b, good, n), wr32(b + 148, 1), reseal(b, n), write_bytes(q, b, n);
    CHECK(refused(q, "byte 148: reserved"));
    double v = 0;
    uint64_t bits;
    memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + 152, bits), reseal(b, n), write_bytes(q, b, n);
    CHECK(refused(q, "byte 152: contrast percentile 0"));
    v = 0.5, memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + rec0 + band0 + 8, bits), reseal(b, n), write_bytes(q, b, n);
    snprintf(want, sizeof want, "byte %zu: level 0: contrast band 1", rec0 + band0 + 8);
    CHECK(refused(q, want));
    v = -0.25, memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + rec1 + band0 + 16, bits), reseal(b, n), write_bytes(q, b, n);
    snprintf(want, sizeof want, "byte %zu: level 1: contrast band 2", rec1 + band0 + 16);
    CHECK(refused(q, want));
    v = INFINITY, memcpy(&bits, &v, 8);
    memcpy(b, good, n), wr64(b + rec1 + band0, bits), reseal(b, n), write_bytes(q, b, n);
    CHECK(refused(q, "level 1: contrast band 0: inf"));
    v = -0.0, memcpy(&bits, &v, 8); /* band 7 of 7: beyond the count, must be zero bytes */
    memcpy(b, good, n), wr64(b + rec1 + band0 + 8 * 7, bits), reseal(b, n), write_bytes(q, b, n);
    snprintf(want, sizeof want, "byte %zu: level 1: contrast band 7", rec1 + band0 + 56);
    CHECK(refused(q, want));
    /* No bands but a percentile: refused; no bands and 0: a valid version 2 file without a spectrum. */
    memcpy(b, good, n), wr32(b + 144, 0), reseal(b, n), write_bytes(q, b, n);
    CHECK(refused(q, "byte 152: contrast percentile 99 (0 without bands)"));
    /* The writer refuses what the reader would. */
    set.lost_contrast[0][2] = 0.1;
    err.msg[0] = 0;
    CHECK(scn_lodfile_write(q, &set, &err) < 0 && strstr(err.msg, "refusing to write") && strstr(err.msg, "level 0"));
    set.lost_contrast[0][2] = 0;
    set.contrast_band_count = 13;
    CHECK(scn_lodfile_write(q, &set, &err) < 0 && strstr(err.msg, "13 contrast bands"));
    free(b);
    free(good);
    unlink(q);
    unlink(p);
    scn_lodset_free(&set);
}

static void on_alarm(int sig) { (void)sig; _exit(3); }

static void test_not_files(void)
{
    const char *fifo = tmp_path("pipe.lod");
    CHECK(mkfifo(fifo, 0600) == 0);
    signal(SIGALRM, on_alarm); /* a reader that blocked on the FIFO would hang here: fail instead */
    alarm(10);
    CHECK(refused(fifo, "not a regular file (a FIFO)"));
    alarm(0);
    unlink(fifo);
    char d[256];
    snprintf(d, sizeof d, "%s", tmp_path("dir.lod"));
    CHECK(mkdir(d, 0700) == 0);
    CHECK(refused(d, "a directory"));
    CHECK(refused(tmp_path("missing.lod"), "cannot open"));
    CHECK(refused("/dev/null", "character device"));
    /* Beyond the size limit: refused from fstat, before any allocation (a sparse file costs nothing). */
    const char *huge = tmp_path("huge.lod");
    FILE *hf = fopen(huge, "wb");
    CHECK(hf && ftruncate(fileno(hf), ((off_t)1 << 31) + 1) == 0);
    if (hf)
        fclose(hf);
    CHECK(refused(huge, "more than the 2 GiB"));
    unlink(huge);
    /* Writing: into a missing directory, over a directory (the rename fails after the temporary
     * file was written), and a lodset the reader would refuse: each fails and leaves nothing. */
    struct scn_lodset set;
    make_set(&set);
    struct hl_error err = {""};
    CHECK(scn_lodfile_write(tmp_path("nowhere/x.lod"), &set, &err) < 0 && strstr(err.msg, "nowhere/x.lod"));
    err.msg[0] = 0;
    int rc = scn_lodfile_write(d, &set, &err);
    printf("  over a directory: rc %d: %s\n", rc, err.msg);
    CHECK(rc < 0 && strstr(err.msg, "nothing written"));
    set.freq[2].geometric_cpdiam = -1;
    err.msg[0] = 0;
    CHECK(scn_lodfile_write(tmp_path("c.lod"), &set, &err) < 0 && strstr(err.msg, "refusing to write") &&
          strstr(err.msg, "frequency -1"));
    set.freq[2].geometric_cpdiam = 2;
    for (int k = 0; k < 8; ++k) /* 12 triangles, as many as level 1 */
        scn_mesh_add_triangle(&set.levels[2], 0, 1, 2);
    err.msg[0] = 0;
    CHECK(scn_lodfile_write(tmp_path("c.lod"), &set, &err) < 0 && strstr(err.msg, "not fewer"));
    set.level_count = 0;
    CHECK(scn_lodfile_write(tmp_path("c.lod"), &set, &err) < 0);
    set.level_count = 3;
    CHECK(access(tmp_path("c.lod"), F_OK) != 0);
    rmdir(d);
    DIR *dd = opendir(dir);
    int entries = 0;
    for (struct dirent *e; dd && (e = readdir(dd));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            ++entries;
            CHECK(strcmp(e->d_name, "a.lod") == 0); /* no .tmp left behind */
        }
    if (dd)
        closedir(dd);
    CHECK(entries == 1);
    scn_lodset_free(&set);
}

int main(void)
{
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_crc();
    test_round_trip();
    test_damage();
    test_nonsense();
    test_v2();
    test_not_files();
    unlink(tmp_path("a.lod"));
    rmdir(dir);
    return tu_finish("lodfile");
}
