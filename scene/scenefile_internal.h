/* Internal to scene/: a scene file as read (scenefile.c) before it becomes a scene (scenefile_build.c).
 * Indices are those of the file; the build reorders groups so that parents come first. */
#ifndef HMDLOD_SCENE_SCENEFILE_INTERNAL_H
#define HMDLOD_SCENE_SCENEFILE_INTERNAL_H

#include "scene/scene_internal.h"

enum sf_builtin { SF_FILE = 0, SF_FIELD_OBJECT, SF_CHAIR, SF_BOX };
enum { SF_PATH_MAX = 4096, SF_WHERE_MAX = 160 };

struct sf_mesh {
    char name[SCN_NAME_MAX];
    char where[SF_WHERE_MAX];  /* JSON path of the entry ("meshes.bunny") */
    enum sf_builtin builtin;
    char given[SF_PATH_MAX];   /* the path as written */
    char path[SF_PATH_MAX];    /* relative to the scene file's folder, or absolute */
    double size_m[3];          /* box */
    int recenter;              /* file: move the model so its bounding-sphere centre is the origin */
};

struct sf_instance {
    char name[SCN_NAME_MAX]; /* "" when unnamed */
    uint32_t mesh;
    hl_vec3d position_m;
    hl_quatd rotation;
    double scale, importance;
    float color[3];
    uint32_t motion; /* index into sf_file.motions, SCN_NONE when still */
};

struct sf_group {
    char name[SCN_NAME_MAX];
    uint32_t parent;        /* file index, SCN_NONE for a root */
    uint32_t impostor_mesh; /* SCN_NONE when none */
    double importance;
    uint32_t motion;
};

struct sf_file {
    const char *file; /* for messages */
    char name[SCN_NAME_MAX];
    struct sf_mesh *meshes;
    uint32_t mesh_count;
    struct sf_instance *instances;
    uint32_t instance_count;
    struct sf_group *groups;
    uint32_t group_count;
    uint32_t *owner;            /* instance_count: the group (file index) listing it, SCN_NONE if none */
    uint32_t *member_order;     /* instance_count: its position in that group's list */
    struct scn_motion *motions; /* only the moving instances and groups */
    uint32_t motion_count;
};
void sf_file_free(struct sf_file *f);

/* Reads and checks path into f (every error "path: json.path: reason"). */
int sf_file_read(const char *path, struct sf_file *f, struct hl_error *err);
/* Makes the scene: meshes through the resolver, instances, the hierarchy ordered parents first with
 * its bounds, motions. On failure *out is freed. */
int sf_file_build(const struct sf_file *f, const struct scn_asset_resolver *resolver, struct scn_scene *out,
                  struct hl_error *err);

#endif
