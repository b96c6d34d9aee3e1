/* Scene files' meshes through the cache: importing a mesh is quick (the bunny in ~0.3 s), while its
 * decimation and the dense Hausdorff sampling of every level take seconds, so the chain is made once
 * and kept as a .lod beside the analysis tables (docs/scene-format.md). */
#include <stdio.h>
#include <string.h>

#include "replay/replay.h"

/* Version of the chain recipe (scn_scenefile_lodgen_params): bump it when that changes. */
enum { RPL_CHAIN_RECIPE = 1 };

static void rpl_stem(const char *path, char *out, size_t size)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t n = 0;
    for (; base[n] && base[n] != '.' && n + 1 < size; ++n) {
        char c = base[n];
        int plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
        out[n] = plain ? c : '_';
    }
    out[n] = '\0';
}

int rpl_resolve_cached(void *user, const char *path, struct scn_lodset *out, struct hl_error *err)
{
    (void)user;
    if (scn_scenefile_path_is_lod(path))
        return scn_lodfile_read(path, out, err);
    struct scn_mesh mesh = {0};
    struct scn_import_report report;
    if (scn_mesh_import(path, &mesh, &report, err) != 0)
        return -1;
    uint64_t hash = scn_mesh_hash(&mesh);
    char dir[4096], file[4600], stem[64];
    struct hl_error dir_err;
    int have_dir = rpl_cache_dir(dir, sizeof dir, &dir_err) == 0;
    rpl_stem(path, stem, sizeof stem);
    if (have_dir)
        snprintf(file, sizeof file, "%s/mesh-%s-%016llx-r%d.lod", dir, stem, (unsigned long long)hash, RPL_CHAIN_RECIPE);
    if (have_dir) {
        struct hl_error read_err = {{0}};
        FILE *probe = fopen(file, "rb");
        if (probe) {
            fclose(probe);
            if (scn_lodfile_read(file, out, &read_err) == 0 && out->source_hash == hash) {
                scn_mesh_free(&mesh);
                return 0;
            }
            scn_lodset_free(out);
            fprintf(stderr, "hmdlod: note: cached chain %s is unusable (%s); rebuilding it from %s\n", file,
                    read_err.msg[0] ? read_err.msg : "made from another mesh", path);
        }
    }
    struct scn_lodgen_params p;
    scn_scenefile_lodgen_params(&p);
    int rc = scn_lodgen_build(&mesh, &p, out, err);
    scn_mesh_free(&mesh);
    if (rc != 0)
        return -1;
    struct hl_error write_err;
    if (have_dir && (rpl_cache_make_dir(dir) != 0 || scn_lodfile_write(file, out, &write_err) != 0))
        fprintf(stderr, "hmdlod: note: cannot keep the chain of %s in %s; it is rebuilt at every load\n", path, dir);
    return 0;
}
