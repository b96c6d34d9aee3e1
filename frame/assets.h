/* frame/assets.h: the measured frequency tables of a scene's chains — Reddy's offline analysis
 * (render/analyze.h) run on the built-in chains once and cached beside the program, and the choice
 * of which reading the selectors use (docs/analysis.md). Part of the frame/frame.h umbrella. */
#ifndef HMDLOD_FRAME_ASSETS_H
#define HMDLOD_FRAME_ASSETS_H

#include "render/render.h"

/* Which frequency of each level the selectors compare against the acuity limit. */
enum frm_freq_reading {
    FRM_READING_LONG = 0,      /* image-based, the longest chord of the largest lost feature */
    FRM_READING_NARROW = 1,    /* image-based, the thickness of the thickest lost feature (default) */
    FRM_READING_GEOMETRIC = 2, /* R / ε from the geometric error (scene.c, no rendering) */
};
/* "long" | "narrow" | "geometric" → the enum; −1 naming the known ones otherwise. */
int frm_freq_reading_parse(const char *name, enum frm_freq_reading *out, struct hl_error *err);
const char *frm_freq_reading_name(enum frm_freq_reading r);

/* The analysis the built-in chains get: 18 views, 256 px, the default threshold and minimum. */
void frm_assets_params(struct rnd_analyze_params *p);

/* Where analysis results are cached: $HMDLOD_CACHE_DIR when set and not empty, else a folder
 * `lodcache` beside the running executable (/proc/self/exe). −1 if neither can be found. */
int frm_cache_dir(char *out, size_t size, struct hl_error *err);
/* Creates the cache folder and its parents if missing; 0 when it exists afterwards, else −1 (errno). */
int frm_cache_make_dir(const char *dir);
/* DIR/LABEL-KEY(16 hex digits)SUFFIX, with LABEL reduced to letters, digits, '-' and '_' (at most 63);
 * −1 if it does not fit in size. */
int frm_cache_file(char *out, size_t size, const char *dir, const char *label, uint64_t key, const char *suffix);

/* The resolver sessions give scene files: scene/'s default with a chain store in the cache, so a
 * mesh file's chain is kept as a .lod named after the file and keyed by scn_mesh_hash of the
 * imported mesh, and a later load reads it instead of decimating again; a changed mesh gets a new
 * key, a corrupt or foreign cache file is rebuilt with a note, an unwritable cache is not an error. */
const struct scn_asset_resolver *frm_cached_resolver(void);

/* Copies chain `chain` of a scene back into a lodset (each level's vertices and local indices, the
 * chain's bounding sphere, errors, frequency tables and lost-contrast spectrum). *out is zeroed first; free it with
 * scn_lodset_free. */
int frm_lodset_from_chain(const struct scn_scene *s, uint32_t chain, struct scn_lodset *out, struct hl_error *err);

struct frm_assets_report {
    uint32_t chains_analysed, chains_cached; /* chains with two or more levels */
    uint32_t chains_from_file;               /* chains whose .lod already held measured tables */
    double analysis_s;                       /* time spent analysing (0 when every chain was cached) */
    int cache_unwritable;                    /* results could not be stored: analysed every run */
};

/* Gives every chain of `scene` with two or more levels its image-based tables — the narrow and long
 * readings and the lost-contrast spectrum (scn_chain.contrast_band_count, contrast_percentile,
 * scn_lod.lost_contrast): a chain that already has both (a version 2 .lod written by `hmdlod
 * analyze`) keeps its own; a chain with readings but no spectrum (a version 1 .lod) keeps its
 * readings and takes the spectrum from the cache or an analysis; others come from the cache when
 * a file with the same key exists (key = the levels' scn_mesh_hash and the analysis parameters, so
 * a changed mesh or parameter never reads a stale table), else by analysis, then stored. A corrupt
 * cache file is analysed again, with a note on stderr; a cache that cannot be written is noted once
 * and is not an error. Then sets every level's unique_freq_cpdiam from `reading`. */
int frm_assets_prepare(struct scn_scene *scene, const struct rnd_analyze_params *p, enum frm_freq_reading reading,
                       struct frm_assets_report *report, struct hl_error *err);
/* The same for one lodset (e.g. what a scene file's asset resolver loaded): fills set->freq[*]
 * .narrow_cpdiam and .long_cpdiam, the spectrum (contrast_band_count, contrast_percentile,
 * lost_contrast) and analysis_views/size_px from the cache or by analysis. name
 * labels the cache file (NULL: "lodset"). A lodset of one level is left as it is. report may be NULL. */
int frm_assets_measure(struct scn_lodset *set, const char *name, const struct rnd_analyze_params *p,
                       struct frm_assets_report *report, struct hl_error *err);
/* Only the last step: unique_freq_cpdiam of every level from `reading` (a level whose image-based
 * reading is NaN — not analysed — keeps the geometric one). */
void frm_assets_apply_reading(struct scn_scene *scene, enum frm_freq_reading reading);

#endif
