/* scene/impostor.h: group impostors (Mason & Blake 1997 §2–3) — one drawable that stands for
 * everything below a group, made by merging the descendants' finest levels in the group's frame
 * and decimating, and checked against the paper's requirement that an impostor "costs less and is
 * worth less than any implicit representation by its children". Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_IMPOSTOR_H
#define HMDLOD_SCENE_IMPOSTOR_H

#include "scene/lodgen.h"
#include "scene/measure.h"

struct scn_scene;

/* The check's numbers. "Children" is every instance below the group, at its finest level and at
 * its coarsest drawable one (the cheapest implicit representation: null impostors aside, §8).
 * Accuracy is Funkhouser & Séquin's 1 − 0.5 / Samples^m (1993 §5) with Samples = vertices and m = 2
 * (Gouraud shading), the merged children counted as one object. */
struct scn_impostor_report {
    uint32_t instances;                              /* instances below the group */
    uint64_t children_triangles_finest, children_vertices_finest;
    uint64_t children_triangles_coarsest, children_vertices_coarsest;
    uint32_t merged_triangles, merged_vertices;      /* the welded merge that was decimated */
    uint32_t impostor_triangles, impostor_vertices;
    struct scn_hausdorff error;                      /* impostor against the merged children, metres */
    double accuracy_impostor, accuracy_children_coarsest, accuracy_children_finest;
    int cheaper, worse;                              /* the two halves of the requirement, 1 = holds */
};

/* Builds group `group`'s impostor of s as a one-level lodset (simplifier "impostor"; level 0 in the
 * group's frame: origin at the group's centre at rest, world axes; error_m[0] its Hausdorff distance
 * to the merged children). Refuses (−1, nothing in *out) a group with nothing below it, a target
 * of 0, and a result that breaks the requirement: not fewer triangles AND vertices than the
 * children at their coarsest, or not worse (Hausdorff error 0, or accuracy not lower). report may
 * be NULL; when given it is filled as far as the build got, refused or not. hausdorff_samples: per
 * mesh for the error (0 = scn_mesh_hausdorff's default, 2^20; fewer widen report->error.bound_m).
 * *out is the caller's to scn_lodset_free. */
int scn_impostor_build_report(const struct scn_scene *s, uint32_t group, enum scn_simplifier simplifier,
                              uint32_t target_triangles, uint64_t hausdorff_samples, struct scn_lodset *out,
                              struct scn_impostor_report *report, struct hl_error *err);
/* The same without the report, default sampling (the agreed entry point). */
int scn_impostor_build(const struct scn_scene *s, uint32_t group, enum scn_simplifier simplifier,
                       uint32_t target_triangles, struct scn_lodset *out, struct hl_error *err);
/* Index of the group named `name`, or SCN_NONE. */
uint32_t scn_scene_find_group(const struct scn_scene *s, const char *name);

#endif
