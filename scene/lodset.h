/* scene/lodset.h: one object's LOD chain as a self-contained asset — what `hmdlod lodgen` makes,
 * what a .lod file holds (docs/lod-format.md), what `hmdlod analyze` measures and what a scene
 * packs into its shared buffers. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_LODSET_H
#define HMDLOD_SCENE_LODSET_H

#include "scene/mesh.h"

enum { SCN_LODSET_MAX_LEVELS = 8 };
/* Octave bands of the lost-contrast spectrum (render/analyze.h): band b is centred on 2^b cycles per
 * object diameter, so 12 bands reach 2048 c/diam, beyond the 2048-px analysis limit's 512. */
enum { SCN_LODSET_MAX_BANDS = 12 };

/* Spatial-frequency table of one level: the highest frequency it loses against the next finer
 * level, in cycles per object diameter (Reddy 1998 §3.2). Level 0 loses nothing: +INFINITY.
 * NaN = not measured (e.g. a .lod written by lodgen before analyze ran). */
struct scn_level_freq {
    double narrow_cpdiam;    /* image-based, from each differing region's narrowest extent */
    double long_cpdiam;      /* image-based, from its longest extent (conservative reading) */
    double geometric_cpdiam; /* R / ε from the geometric error (docs/scenes.md) */
};

/* Levels are ordered finest (0) to coarsest, each with fewer triangles than the one before. The
 * lodset owns its meshes; scn_lodset_free releases them and zeroes the struct. */
struct scn_lodset {
    int level_count; /* 1…SCN_LODSET_MAX_LEVELS */
    struct scn_mesh levels[SCN_LODSET_MAX_LEVELS];
    double error_m[SCN_LODSET_MAX_LEVELS];   /* two-sided Hausdorff distance to level 0, metres */
    double error_rel[SCN_LODSET_MAX_LEVELS]; /* error_m / radius_m */
    struct scn_level_freq freq[SCN_LODSET_MAX_LEVELS];
    double center_m[3];                      /* bounding-sphere centre, model space */
    double radius_m;                         /* bounding-sphere radius about center_m */
    double aabb_min_m[3], aabb_max_m[3];     /* of level 0 */
    uint64_t source_hash;                    /* FNV-1a 64 of the source mesh's welded arrays */
    char simplifier[16];                     /* "openmesh", "meshopt", "procedural", "impostor" */
    int analysis_views, analysis_size_px;    /* 0 until analysed */
    /* The lost-contrast spectrum (render/analyze.h, docs/analysis.md): lost_contrast[l][b] is the
     * band-limited contrast of level l's difference from level 0 in octave band b (2^b cycles per
     * diameter), the contrast_percentile-th percentile of each view's object pixels, maximum over
     * views; level 0 is 0 in every band. contrast_band_count 0: not measured (a version 1 .lod, or
     * lodgen before analyze), the rest then unused. */
    int contrast_band_count;
    double contrast_percentile;
    double lost_contrast[SCN_LODSET_MAX_LEVELS][SCN_LODSET_MAX_BANDS];
};
void scn_lodset_free(struct scn_lodset *set);

/* Writes `set` to `path` atomically (temporary file, fsync, rename): a reader never sees a
 * half-written .lod. Versioned and CRC-32-checked; format in docs/lod-format.md. */
int scn_lodfile_write(const char *path, const struct scn_lodset *set, struct hl_error *err);
/* Reads a .lod file. Bad magic, unknown version, a checksum mismatch, a truncated body or values
 * that make no sense (NaN positions, indices out of range, counts beyond the file) are refused with
 * "path: byte OFFSET: reason"; on failure *out is left zeroed. */
int scn_lodfile_read(const char *path, struct scn_lodset *out, struct hl_error *err);

#endif
