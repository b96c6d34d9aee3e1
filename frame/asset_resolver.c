/* Scene files' meshes through the cache: importing a mesh is quick (the bunny in ~0.3 s), while its
 * decimation and the dense Hausdorff sampling of every level take seconds, so the chain is made once
 * and kept as a .lod beside the analysis tables (docs/scene-format.md). A chain store for scene/'s
 * default resolver (scene/scenefile.h). */
#include <stdio.h>
#include <sys/stat.h>
#include <string.h>

#include "frame/frame.h"

/* Version of the default resolver's chain recipe (scene/scenefile_build.c): bump it when that changes. */
enum { FRM_CHAIN_RECIPE = 2 }; /* 2: crease normals on every level */

/* lodcache/mesh-STEM-HASH-rN.lod, STEM the mesh file's name up to its first '.'; −1 when the cache
 * folder cannot be named. */
static int frm_chain_path(const char *mesh_path, uint64_t hash, char *dir, size_t dir_size, char *out, size_t size)
{
    struct hl_error err;
    if (frm_cache_dir(dir, dir_size, &err) != 0)
        return -1;
    const char *base = strrchr(mesh_path, '/');
    base = base ? base + 1 : mesh_path;
    char label[64], suffix[16];
    snprintf(label, sizeof label, "mesh-%.*s", (int)strcspn(base, "."), base);
    snprintf(suffix, sizeof suffix, "-r%d.lod", FRM_CHAIN_RECIPE);
    return frm_cache_file(out, size, dir, label, hash, suffix);
}

static int frm_chain_load(void *user, const char *path, uint64_t hash, struct scn_lodset *out)
{
    (void)user;
    char dir[4096], file[4600];
    if (frm_chain_path(path, hash, dir, sizeof dir, file, sizeof file) != 0)
        return -1;
    struct stat st;
    if (stat(file, &st) != 0)
        return -1; /* not made yet (anything else there is reported by scn_lodfile_read) */
    struct hl_error err = {{0}};
    if (scn_lodfile_read(file, out, &err) == 0 && out->source_hash == hash)
        return 0;
    scn_lodset_free(out);
    fprintf(stderr, "hmdlod: note: cached chain %s is unusable (%s); rebuilding it from %s\n", file,
            err.msg[0] ? err.msg : "made from another mesh", path);
    return -1;
}

static void frm_chain_save(void *user, const char *path, uint64_t hash, const struct scn_lodset *set)
{
    (void)user;
    char dir[4096], file[4600];
    struct hl_error err = {{0}};
    if (frm_chain_path(path, hash, dir, sizeof dir, file, sizeof file) != 0 || frm_cache_make_dir(dir) != 0 ||
        scn_lodfile_write(file, set, &err) != 0)
        fprintf(stderr, "hmdlod: note: cannot keep the chain of %s in the cache%s%s; it is rebuilt at every load\n",
                path, err.msg[0] ? ": " : "", err.msg);
}

static const struct scn_chain_store frm_chain_store = {frm_chain_load, frm_chain_save, NULL};
static const struct scn_asset_resolver frm_resolver = {scn_scenefile_resolve_default, (void *)&frm_chain_store};

const struct scn_asset_resolver *frm_cached_resolver(void) { return &frm_resolver; }
