/* scene/lodgen_internal.h: what the import readers, the validation pass and the two simplifiers
 * share inside scene/ (lodgen.h is the public side). The C++ shims (mesh_import.cpp,
 * decimate_openmesh.cpp) implement the scn_om_* functions behind extern "C". */
#ifndef HMDLOD_SCENE_LODGEN_INTERNAL_H
#define HMDLOD_SCENE_LODGEN_INTERNAL_H

/* base/ and scene/ headers are C: their declarations get C linkage in the C++ shims too. */
#ifdef __cplusplus
extern "C" {
#endif

#include <stdio.h>

#include "scene/scene.h"

/* ---- import ------------------------------------------------------------------------------------
 * A reader's raw result, before validation: vertices in file order and triangles (polygons already
 * fanned), each triangle remembering the file's face number it came from (0-based) so that a
 * message can name it. All arrays malloc'd; scn_soup_free releases them. */
struct scn_soup {
    double *positions;    /* 3 per vertex, as read (NaN/Inf possible) */
    float *normals;       /* 3 per vertex or NULL: the file's vertex normals */
    uint32_t vertex_count;
    uint32_t *indices;    /* 3 per triangle, < vertex_count */
    uint32_t *face_of_tri; /* 1 per triangle */
    uint32_t triangle_count, triangle_cap;
    uint32_t faces_read, polygons_triangulated;
    uint32_t bad_index_faces;      /* faces naming a vertex that does not exist (skipped) */
    uint32_t first_bad_index_face; /* the first of them */
    int failed;                    /* out of memory */
    char reader_note[160];         /* the reader's first complaint, if any ("" if none) */
};
void scn_soup_free(struct scn_soup *s);
/* Appends one file face (n ≥ 3 vertex indices) as n − 2 triangles. Quads split along the shorter
 * diagonal (no fold for a convex or mildly non-planar quad); larger polygons are fanned. Faces with
 * fewer than 3 vertices or an index ≥ vertex_count are counted, not added. */
void scn_soup_add_face(struct scn_soup *s, const uint32_t *idx, uint32_t n);

/* Reads OBJ/PLY/OFF/STL through OpenMesh's IO into `soup` (mesh_import.cpp); OpenMesh's own log is
 * kept off stdout/stderr and its error text, if any, goes into the message. faces_follow: the
 * caller adds faces of its own (a PLY's strips), so a reader that stopped with vertices but no faces
 * is not refused here. */
int scn_om_read(const char *path, struct scn_soup *soup, int faces_follow, struct hl_error *err);
/* The triangles of a PLY file's "tristrips" elements (lists of vertex_indices, −1 between strips),
 * which OpenMesh does not read: decoded by scn_ply_check, wound as the strips say (odd triangles
 * reversed), triangles with a repeated index left out. Indices are < the file's vertex count. */
struct scn_ply_strips {
    uint32_t *indices; /* 3 per triangle */
    uint32_t triangle_count, triangle_cap;
    uint32_t elements; /* tristrips elements in the file */
    uint64_t items;    /* indices read, −1 included */
};
void scn_ply_strips_free(struct scn_ply_strips *s);
/* A PLY file before OpenMesh reads it (mesh_ply_check.c): its header line by line (what OpenMesh's
 * header loop ends on), then every record of every element walked, list sizes bounded (a face's by
 * 4096, a strip's by what the file still holds), so that what OpenMesh allocates follows from the
 * file's real content; or an error naming the line or record. The strips are decoded on the way
 * into *strips (may be NULL: checked only; freed on error). */
int scn_ply_check(const char *path, struct scn_ply_strips *strips, struct hl_error *err);
/* An OFF file before OpenMesh reads it (mesh_off_check.c): a keyword OpenMesh reads, counts that fit
 * the file, the vertex lines, and every face's size and indices. Text OFF only. */
int scn_off_check(const char *path, uint64_t file_size, struct hl_error *err);
/* A glTF 2.0 file (.gltf, or .glb when glb) before assimp reads it (mesh_gltf_check.c): the magic or
 * '{', a .glb's chunks inside the file, then its JSON: buffer views inside their buffers, accessors
 * and sparse accessors inside their views, zero-filled accessors bounded. Or an error naming them. */
int scn_gltf_check(const char *path, int glb, uint64_t file_size, struct hl_error *err);
/* What iostream >> skips in the C locale (isspace): the blanks OpenMesh's readers split words at. */
extern const char scn_lex_blanks[];
/* Text reading shared by the two checks (mesh_lex.c). A line without its newline into buf: 0, or
 * −1 at the end of the file before a newline, −2 for a line longer than buf, −3 for a NUL byte. */
int scn_lex_line(FILE *f, char *buf, size_t size);
/* Splits line in place at blanks into at most max_words + 1 words (the extra one only counts). */
int scn_lex_words(char *line, char **w, int max_words);
/* 1 if s is a whole number of at most 10 digits that fits an int (OpenMesh reads counts as int). */
int scn_lex_is_count(const char *s);
/* 1 if the whole of s is a number strtod reads. */
int scn_lex_is_number(const char *s);
/* The next blank-separated token into buf: 0, −1 at the end of the file, −2 too long, −3 NUL byte.
 * *line counts the newlines passed; *newline_before says whether one came before this token. */
int scn_lex_token(FILE *f, char *buf, size_t size, uint64_t *line, int *newline_before);
/* Reads glTF 2.0 (.gltf/.glb) through assimp's C API (mesh_import_assimp.c), node transforms baked. */
int scn_assimp_read(const char *path, struct scn_soup *soup, struct hl_error *err);

/* Validates and welds a soup into a triangle mesh (mesh_validate.c): NaN/Inf refused with the vertex
 * number, exact-position welding, zero-area faces dropped and counted, non-manifold edges counted
 * (edges with more than two faces: a warning, the mesh is kept), normals from the file or
 * area-weighted. `path` only names the file in messages. */
int scn_soup_to_mesh(const char *path, struct scn_soup *soup, struct scn_mesh *out,
                     struct scn_import_report *report, struct hl_error *err);

/* Merges vertices at bit-identical positions (−0 = +0), drops unused vertices and triangles that
 * collapse to repeated indices; normals recomputed area-weighted. Returns the number merged, or −1
 * on allocation failure (mesh left as it was). Used on simplifier output too. */
long scn_mesh_weld_exact(struct scn_mesh *m);
/* Edges with more than two incident triangles (undirected), in an indexed mesh; −1 if out of memory.
 * *example_a/_b get one such edge's vertices when the count is non-zero (may be NULL). */
long scn_mesh_count_nonmanifold_edges(const struct scn_mesh *m, uint32_t *example_a, uint32_t *example_b);

/* ---- decimation --------------------------------------------------------------------------------- */
/* Told after each level of a chain is done (level 0 = the first target); may be NULL. */
struct scn_chain_observer {
    void (*level_done)(void *user, int level);
    void *user;
};
/* One OpenMesh DecimaterT (ModQuadricT priority, ModNormalFlippingT guard) run through the
 * targets in turn (strictly decreasing triangle counts), garbage collection between levels
 * (PLATFORM.md §7b); outs[k] gets level k's welded mesh with area-weighted normals. Edges with
 * dihedral angle > feature_angle_deg are features (feature_angle_deg < 0: none); feature-line
 * corners (three or more feature edges) are locked; so is the open boundary until a level cannot
 * be reached with it, then it is freed for the rest of the chain. Stops early without error where no collapse is legal. */
int scn_om_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                          double feature_angle_deg, struct scn_mesh *outs, struct scn_decimate_timing *timing,
                          const struct scn_chain_observer *obs, struct hl_error *err);
/* The same with meshoptimizer (decimate_meshopt.c): each level simplified from the previous one. */
int scn_meshopt_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                               struct scn_mesh *outs, const struct scn_chain_observer *obs, struct hl_error *err);

/* scn_mesh_decimate_chain with a per-level observer (lodgen.c; timing may be NULL). */
int scn_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                       enum scn_simplifier simplifier, double feature_angle_deg, struct scn_mesh *outs,
                       struct scn_decimate_timing *timing, const struct scn_chain_observer *obs,
                       struct hl_error *err);

#ifdef __cplusplus
}
#endif

#endif
