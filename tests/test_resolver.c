/* Scene files' mesh entries through replay's caching resolver (frame/asset_resolver.c): the first
 * load makes the chain and keeps it as a .lod in the cache, a later load reads that file (proved by
 * planting a marked copy), a corrupt or foreign cache file is rebuilt, an unwritable cache is not an
 * error, a .lod entry passes straight through, a lodset's lost-contrast spectrum reaches its chain, and
 * a .lod's own measured tables are used as they are. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "frame/frame.h"
#include "test_util.h"

/* The one cache file for suzanne in dir, or "" when there is none. */
static int find_cached(const char *dir, char *out, size_t size)
{
    DIR *d = opendir(dir);
    int found = 0;
    if (!d)
        return 0;
    for (struct dirent *e; (e = readdir(d));)
        if (!strncmp(e->d_name, "mesh-suzanne-", 13) && strstr(e->d_name, ".lod") && !strstr(e->d_name, ".tmp")) {
            snprintf(out, size, "%s/%s", dir, e->d_name);
            ++found;
        }
    closedir(d);
    return found;
}

static int resolve(const char *path, struct scn_lodset *out, struct hl_error *err)
{
    const struct scn_asset_resolver *r = frm_cached_resolver();
    return r->resolve(r->user, path, out, err);
}

int main(void)
{
    const char *mesh = tu_shared_path("data/meshes/suzanne.obj");
    if (!mesh)
        return 77;
    char mesh_path[4096];
    snprintf(mesh_path, sizeof mesh_path, "%s", mesh);
    char dir[] = "/tmp/hmdlod-test-resolver-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    setenv("HMDLOD_CACHE_DIR", dir, 1);
    struct hl_error err = {{0}};

    /* First load: built and kept. */
    struct scn_lodset first = {0};
    CHECK(resolve(mesh_path, &first, &err) == 0);
    CHECK(first.level_count == 4);
    char cached[4600] = "";
    CHECK(find_cached(dir, cached, sizeof cached) == 1);

    /* A marked copy planted in its place is what the next load returns: the cache is read. */
    struct scn_lodset marked = {0};
    CHECK(scn_lodfile_read(cached, &marked, &err) == 0);
    CHECK(marked.source_hash == first.source_hash);
    marked.error_m[1] = 0.123456;
    CHECK(scn_lodfile_write(cached, &marked, &err) == 0);
    struct scn_lodset second = {0};
    CHECK(resolve(mesh_path, &second, &err) == 0);
    CHECK(second.error_m[1] == 0.123456);
    CHECK(second.level_count == first.level_count);
    for (int l = 0; l < first.level_count && l < second.level_count; ++l)
        CHECK(second.levels[l].index_count == first.levels[l].index_count &&
              !memcmp(second.levels[l].positions, first.levels[l].positions,
                      3 * sizeof(float) * first.levels[l].vertex_count));
    scn_lodset_free(&second);

    /* A cache file from another mesh (another source hash) is rebuilt, not trusted. */
    marked.source_hash ^= 1;
    CHECK(scn_lodfile_write(cached, &marked, &err) == 0);
    CHECK(resolve(mesh_path, &second, &err) == 0);
    CHECK(second.error_m[1] == first.error_m[1]);
    scn_lodset_free(&second);
    scn_lodset_free(&marked);

    /* A corrupt one (a flipped byte fails the CRC) is rebuilt and rewritten valid. */
    FILE *f = fopen(cached, "r+b");
    CHECK(f != NULL);
    if (f) {
        fseek(f, 200, SEEK_SET);
        int c = fgetc(f);
        fseek(f, 200, SEEK_SET);
        fputc(c ^ 0x40, f);
        fclose(f);
    }
    CHECK(resolve(mesh_path, &second, &err) == 0);
    CHECK(second.error_m[1] == first.error_m[1]);
    scn_lodset_free(&second);
    CHECK(scn_lodfile_read(cached, &second, &err) == 0);
    scn_lodset_free(&second);

    /* A .lod entry is read as it is (the cache file itself will do). */
    CHECK(resolve(cached, &second, &err) == 0);
    CHECK(second.source_hash == first.source_hash);
    scn_lodset_free(&second);

    /* A cache that cannot be made is not an error: the chain is built anyway. */
    setenv("HMDLOD_CACHE_DIR", "/proc/hmdlod-no-such-dir/cache", 1);
    CHECK(resolve(mesh_path, &second, &err) == 0);
    CHECK(second.level_count == first.level_count);
    scn_lodset_free(&second);

    /* A missing mesh names itself. */
    CHECK(resolve("/tmp/hmdlod-no-such-mesh.obj", &second, &err) != 0);
    CHECK(strstr(err.msg, "hmdlod-no-such-mesh.obj") != NULL);

    /* A chain whose .lod already holds measured tables — readings and spectrum, a version 2 file —
     * keeps them: nothing is analysed again. (A version 1 file, readings only, is analysed for its
     * spectrum: test_analyze, which may render.) */
    for (int l = 1; l < first.level_count; ++l)
        first.freq[l].narrow_cpdiam = 40.0 / l, first.freq[l].long_cpdiam = 20.0 / l;
    first.freq[0].narrow_cpdiam = first.freq[0].long_cpdiam = INFINITY;
    first.analysis_views = 18, first.analysis_size_px = 256; /* as `hmdlod analyze` leaves it */
    first.contrast_band_count = 7, first.contrast_percentile = 99;
    for (int l = 1; l < first.level_count; ++l)
        for (int b = 0; b < first.contrast_band_count; ++b)
            first.lost_contrast[l][b] = 0.001 * (b + 1) * l + 1e-17 * b; /* bits a rounding would lose */
    first.lost_contrast[1][6] = NAN; /* no view had an object pixel in that band */
    first.lost_contrast[2][9] = 5.0; /* beyond the band count: unused, must not reach the chain */
    struct scn_scene scene = {0};
    CHECK(scn_scene_add_lodset(&scene, "measured", &first, &err) == 0);
    /* The lodset's spectrum is the chain's, bit for bit, unused bands 0. */
    const struct scn_chain *ch = &scene.chains[0];
    CHECK(ch->contrast_band_count == 7 && ch->contrast_percentile == 99);
    for (int l = 0; l < first.level_count; ++l)
        for (int b = 0; b < SCN_LODSET_MAX_BANDS; ++b) {
            double want = b < 7 ? first.lost_contrast[l][b] : 0.0;
            CHECK(memcmp(&ch->lods[l].lost_contrast[b], &want, sizeof want) == 0);
        }
    CHECK(isnan(ch->lods[1].lost_contrast[6]) && ch->lods[2].lost_contrast[9] == 0.0);
    /* More bands than a chain holds is refused before anything is packed. */
    struct scn_scene refused = {0};
    first.contrast_band_count = SCN_LODSET_MAX_BANDS + 1;
    CHECK(scn_scene_add_lodset(&refused, "too-many-bands", &first, &err) != 0 && strstr(err.msg, "contrast bands"));
    CHECK(refused.chain_count == 0);
    scn_scene_free(&refused);
    first.contrast_band_count = 7;
    struct rnd_analyze_params ap;
    frm_assets_params(&ap);
    struct frm_assets_report rep;
    CHECK(frm_assets_prepare(&scene, &ap, FRM_READING_NARROW, &rep, &err) == 0);
    CHECK(rep.chains_from_file == 1 && rep.chains_analysed == 0 && rep.chains_cached == 0);
    CHECK(scene.chains[0].lods[2].unique_freq_cpdiam == 20.0);
    CHECK(scene.chains[0].contrast_band_count == 7 &&
          scene.chains[0].lods[3].lost_contrast[2] == first.lost_contrast[3][2]);
    scn_scene_free(&scene);

    scn_lodset_free(&first);
    remove(cached);
    rmdir(dir);
    return tu_finish("resolver");
}
