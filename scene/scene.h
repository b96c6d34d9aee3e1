/* scene: what the world holds, on the CPU — meshes, LOD chains, instances and the built-in
 * procedural scenes. Prefix scn_. Knows nothing of OpenGL: render/ uploads and draws what this
 * module holds; lod/ and acuity/ see it only as arrays. */
#ifndef HMDLOD_SCENE_H
#define HMDLOD_SCENE_H

#include "base/base.h"
#include "scene/lodset.h"
#include "scene/mesh.h"

enum { SCN_MAX_LODS = 8, SCN_NAME_MAX = 32 };

/* ---- scenes ------------------------------------------------------------------------------------
 * All chains' vertices and indices live in one packed array each; an LOD is a range in them. */
struct scn_lod {
    uint32_t first_index, index_count; /* range in scene.indices (3 per triangle) */
    uint32_t triangle_count, vertex_count;
    double geometric_error_m;  /* max distance from the finest level's vertices to this level's surface */
    double unique_freq_cpdiam; /* the reading the selectors use (see acuity.h, docs/scenes.md) */
    struct scn_level_freq freq; /* every reading known for this level (lodset.h) */
    /* lodset.h: band b (2^b cycles per diameter) contrast lost against level 0 */
    double lost_contrast[SCN_LODSET_MAX_BANDS];
    /* Mean front-facing projected area over all view directions, model units² at scale 1: a quarter
     * of the level's surface area (Cauchy's projection formula; back faces are culled). What the
     * rasteriser fills, overdraw of front faces included (scn_lod_fill). */
    double front_area_m2;
};

struct scn_chain {
    char name[SCN_NAME_MAX];
    int lod_count;
    struct scn_lod lods[SCN_MAX_LODS];
    double bound_center_m[3]; /* bounding-sphere centre, model space (the origin for the built-ins) */
    double bound_radius_m;    /* bounding-sphere radius about bound_center_m, at scale 1 */
    double box_min_m[3], box_max_m[3]; /* model-space box around every level's vertices, at scale 1
                                        * (projected coverage of large objects, frame/select.c) */
    int null_impostor; /* 1: drawing nothing (lod 255) is a legal choice for its instances (Mason & Blake §8) */
    int analysis_views, analysis_size_px; /* of the image-based tables its asset (.lod) came with; 0: none */
    /* The lost-contrast spectrum (lodset.h, docs/analysis.md): lods[l].lost_contrast[0 …
     * contrast_band_count − 1], from the asset (a version 2 .lod) or from frm_assets_prepare (the
     * cache or an analysis). Level 0 is 0 in every band; a band may be NaN (no view had an object
     * pixel in it); bands from contrast_band_count on are unused (0). */
    int contrast_band_count;     /* 0: not measured */
    double contrast_percentile;  /* of each view's object pixels behind each value, (0, 100]; 0 when not measured */
};

/* The share of a projected bound that level `level` of chain ch fills, on average over view
 * directions: its front_area_m2 over the bound's mean projected area — the bounding sphere's disc,
 * π·r² (box 0), or the model box's, a quarter of its surface (box 1; Cauchy). The cost model charges
 * pixels_px × fill (frame/select.c): a chair fills a fraction of its disc, a sphere about all of it,
 * and an object whose front faces overlap more than 1. 1 where the bound has no area. */
double scn_lod_fill(const struct scn_chain *ch, int level, int box);

struct scn_instance {
    uint32_t chain;
    double position_m[3];
    hl_quatd rotation; /* model to world, w x y z */
    double scale;
    float color[3];
};

/* The hierarchy (Mason & Blake 1997 §2): groups hold instances and child groups; a group may have an
 * impostor, a chain drawn instead of everything below it. Culling walks groups so that a culled
 * group costs one sphere test. A scene without groups has none (group_count 0) and is flat. */
enum { SCN_NONE = UINT32_MAX };
struct scn_group {
    char name[SCN_NAME_MAX];
    uint32_t parent;                          /* SCN_NONE for a root */
    uint32_t first_child, child_count;        /* child groups: group_children[first_child …] */
    uint32_t first_instance, instance_count;  /* own instances: group_instances[first_instance …] */
    uint32_t impostor_chain;                  /* SCN_NONE, or the chain drawn for the whole group */
    uint32_t impostor_instance;               /* SCN_NONE, or the instance that draws it (see below) */
    double importance;                        /* Funkhouser's Importance, default 1 */
    double center_m[3], radius_m;             /* world bounding sphere of everything below */
};

struct scn_scene {
    char name[SCN_NAME_MAX];
    float *positions; /* 3 per vertex, model space */
    float *normals;   /* 3 per vertex */
    uint32_t vertex_count;
    uint32_t *indices; /* absolute vertex indices */
    uint32_t index_count;
    struct scn_chain *chains;
    uint32_t chain_count;
    /* instances[0 … instance_count − 1] are the scene's objects. The group impostors' instances
     * follow them, instances[instance_count … + impostor_instance_count − 1] (and the per-instance
     * arrays center_m, radius_m, chain_of_instance, importance have room for them): each sits at its
     * group's frame (origin at the group's rest centre, moved with the group by frm_motion_step), is
     * drawn only when an optimizer chooses the impostor, and is no scene object — culling, acuity,
     * summaries and every loop up to instance_count never see it. */
    struct scn_instance *instances;
    uint32_t instance_count;
    uint32_t impostor_instance_count;
    double *center_m; /* world bounding-sphere centres, 3 per instance (structure of arrays for acuity) */
    double *radius_m; /* world bounding-sphere radii, 1 per instance */
    uint32_t *chain_of_instance;
    double *importance; /* 1 per instance, Funkhouser's Importance; NULL (built-in scenes): all 1 */
    struct scn_group *groups; /* parents before children */
    uint32_t group_count;
    uint32_t *group_children, *group_instances; /* index lists the groups' ranges point into */
    struct scn_motion_set *motion; /* motion paths and rest poses (scene/motion.h); NULL = static */
};

struct scn_scene_params {
    int object_count; /* field: 1…100000, 0 = default 100 (auditorium ignores it) */
    uint64_t seed;    /* placement seed (default 1) */
};

/* Appends one drawable instance per group with an impostor chain after the objects (see struct
 * scn_scene) and sets every group's impostor_instance (SCN_NONE without impostor). Call once the
 * groups' rest centres are final; the instance's colour is that of the first instance below the
 * group. Builders call it; 0 or −1 (out of memory). */
int scn_scene_add_impostor_instances(struct scn_scene *s, struct hl_error *err);

/* Built-in scenes: "field" (Reddy §5: N copies of one object with 4 LODs of about 3928/834/254/76
 * triangles, randomly placed around the viewer) and "auditorium" (Funkhouser §7: rows of chairs
 * with several LODs, walls and a stage, ~90k triangles at full detail). Deterministic for a seed. */
int scn_scene_build(const char *name, const struct scn_scene_params *params, struct scn_scene *out,
                    struct hl_error *err);
void scn_scene_free(struct scn_scene *scene);
const char *const *scn_scene_builtin_names(void); /* NULL-terminated */

#include "scene/lodgen.h"
#include "scene/measure.h"
#include "scene/motion.h"
#include "scene/impostor.h"
#include "scene/scenefile.h"
#include "scene/cull.h"

#endif
