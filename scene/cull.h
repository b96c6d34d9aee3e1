/* scene/cull.h: visibility of bounding spheres against a convex set of planes, walking the group
 * hierarchy (Clark 1976; Mason & Blake 1997 §2) so that a group outside one plane costs one sphere
 * test and a group inside every plane accepts its subtree untested. Pure geometry on the scene's
 * arrays; nothing is allocated per call. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_CULL_H
#define HMDLOD_SCENE_CULL_H

#include "base/base.h"

struct scn_scene;

enum { SCN_CULL_MAX_PLANES = 16 };

/* A half-space: a point p is inside when normal·p + offset_m ≥ 0; normal unit, world frame. */
struct scn_plane {
    double normal[3];
    double offset_m;
};

/* What one cull did. A "test" is one sphere against the planes still undecided for it (at most all
 * of them, each plane test counted in plane_tests). */
struct scn_cull_stats {
    uint32_t groups_tested;    /* group spheres tested */
    uint32_t groups_visible;   /* groups not culled: tested and kept, or accepted inside a parent */
    uint32_t instances_tested; /* instance spheres tested */
    uint32_t instances_visible;
    uint64_t plane_tests;      /* sphere–plane tests in all */
};

/* Scratch for scn_cull, sized once for a scene: the walk's stack and the list of instances that no
 * group holds. scn_culler_init allocates; scn_culler_free releases and zeroes. The scene's group
 * arrays must not change between init and the culls. */
struct scn_culler {
    uint32_t *stack_group, *stack_mask; /* one entry per group at most */
    uint32_t stack_cap;
    uint32_t *loose; /* instances in no group, ascending */
    uint32_t loose_count;
    uint32_t *roots; /* groups without a parent, ascending */
    uint32_t root_count;
};
int scn_culler_init(struct scn_culler *c, const struct scn_scene *s, struct hl_error *err);
void scn_culler_free(struct scn_culler *c);

/* Writes the indices of the instances whose world sphere (s->center_m, s->radius_m) is not wholly
 * outside one of the planes to visible (room for s->instance_count) and returns their count.
 * Flat scenes (group_count 0) test each instance in index order; otherwise instances in no group
 * come first (ascending), then the groups' instances in depth-first order from the roots.
 * plane_count ≤ SCN_CULL_MAX_PLANES; stats may be NULL. */
uint32_t scn_cull(const struct scn_scene *s, const struct scn_plane *planes, int plane_count,
                  struct scn_culler *c, uint32_t *visible, struct scn_cull_stats *stats);
/* The same set by testing every instance against every plane, ignoring groups (reference, bench). */
uint32_t scn_cull_flat(const struct scn_scene *s, const struct scn_plane *planes, int plane_count,
                       uint32_t *visible, struct scn_cull_stats *stats);

/* ---- the hierarchy's invariants ---------------------------------------------------------------- */
/* Checks the group arrays: parents before children, each child listed once under its parent, ranges
 * inside group_children / group_instances, every instance in at most one group. 0, or −1 with
 * "scene NAME: groups[i] (NAME): what". */
int scn_scene_check_groups(const struct scn_scene *s, struct hl_error *err);
/* Sets every group's world sphere (center_m, radius_m) to contain its instances' spheres and its
 * child groups' spheres, children first (call after the instances are placed). A group with no
 * instance below it gets radius_m −1 at the origin: its parent's bound ignores it, culling skips it. */
void scn_scene_group_bounds(struct scn_scene *s);

#endif
