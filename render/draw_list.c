/* One view's draw list (render_internal.h rnd_draw_view): the entries a layer draws, in batches of
 * the instances that share a chain, a level and a colour — one instanced draw each —, nearest batch
 * first; their transforms, and each instance's albedo as the fragment shader takes it (renderer.c).
 * Arrays sized once per uploaded scene, so that drawing allocates nothing. */
#include "render/render_internal.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <cglm/cglm.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Light from above, a little to the right and behind the default view, fixed in the world so that
 * shading stays put when the head turns. */
static const double rnd_light_world[3] = {0.35, 0.85, 0.4};

int rnd_draw_list_reserve(struct rnd_draw_list *l, size_t entries)
{
    if (entries > l->cap) {
        struct rnd_draw_entry *e = realloc(l->entries, entries * sizeof *e);
        if (e)
            l->entries = e;
        struct rnd_draw_batch *b = realloc(l->batches, entries * sizeof *b);
        if (b)
            l->batches = b;
        float *t = realloc(l->transforms, entries * 16 * sizeof *t);
        if (t)
            l->transforms = t;
        struct rnd_albedo *a = realloc(l->albedo, entries * sizeof *a);
        if (a)
            l->albedo = a;
        if (!e || !b || !t || !a)
            return -1;
        l->cap = entries;
    }
    for (size_t k = 0; k < entries; ++k) /* none made yet; every byte set, for the cache's memcmp */
        l->albedo[k].srgb[0] = l->albedo[k].srgb[1] = l->albedo[k].srgb[2] = NAN;
    return 0;
}

void rnd_draw_list_free(struct rnd_draw_list *l)
{
    free(l->entries);
    free(l->batches);
    free(l->transforms);
    free(l->albedo);
    memset(l, 0, sizeof *l);
}

/* Column-major 4×4 of the model-to-eye transform. The eye-relative part is done in double — the
 * translation is the instance position minus the eye position, so an object 1e6 m from the origin
 * but 2 m from the eye keeps millimetre precision (float world matrices would lose ~6 cm there) —
 * and only then does GL-side float math take over, through cglm (DESIGN.md: cglm's versor is x y z w). */
static void rnd_model_view(const struct scn_instance *in, const struct rnd_eye_view *v, float out[16])
{
    hl_quatd to_eye = hl_q_conj(v->orientation);
    hl_quatd q = hl_q_mul(to_eye, in->rotation);
    hl_vec3d t = hl_q_rotate(to_eye, hl_v3(in->position_m[0] - v->position_m[0], in->position_m[1] - v->position_m[1],
                                           in->position_m[2] - v->position_m[2]));
    versor qf = {(float)q.x, (float)q.y, (float)q.z, (float)q.w};
    mat4 m;
    glm_quat_mat4(qf, m);
    glm_scale_uni(m, (float)in->scale);
    m[3][0] = (float)t.x, m[3][1] = (float)t.y, m[3][2] = (float)t.z;
    memcpy(out, m, sizeof m);
}

/* Whether draw-list entry k is drawn in the layer of layer_bit (mask NULL: every layer). */
static int rnd_entry_drawn(const struct scn_scene *scene, const uint32_t *index, const uint8_t *lod,
                           const uint8_t *mask, unsigned layer_bit, size_t k)
{
    if (lod[k] == 255 || (mask && !(mask[k] & layer_bit)))
        return 0;
    return scene->chains[scene->instances[index[k]].chain].lods[lod[k]].index_count > 0;
}

/* Shell sort on Ciura's gaps (extended by × 2.25 for lists of up to ~10⁵): no allocation,
 * microseconds for a hundred elements. */
#define RND_SHELL_SORT(array, n, type, before)                                                                   \
    do {                                                                                                         \
        static const size_t gaps_[] = {100894, 44842, 19930, 8858, 3937, 1750, 701, 301, 132, 57, 23, 10, 4, 1}; \
        for (size_t g_ = 0; g_ < sizeof gaps_ / sizeof gaps_[0]; ++g_)                                           \
            for (size_t i_ = gaps_[g_]; i_ < (n); ++i_) {                                                        \
                type e_ = (array)[i_];                                                                           \
                size_t j_ = i_;                                                                                  \
                for (; j_ >= gaps_[g_] && before(&e_, &(array)[j_ - gaps_[g_]]); j_ -= gaps_[g_])                \
                    (array)[j_] = (array)[j_ - gaps_[g_]];                                                       \
                (array)[j_] = e_;                                                                                \
            }                                                                                                    \
    } while (0)

/* Entries of one batch (same chain, level and colour) together, each batch nearest first. */
static int rnd_entry_before(const struct rnd_draw_entry *a, const struct rnd_draw_entry *b)
{
    if (a->chain != b->chain)
        return a->chain < b->chain;
    if (a->level != b->level)
        return a->level < b->level;
    int c = memcmp(a->color, b->color, sizeof a->color);
    if (c != 0)
        return c < 0;
    return a->depth2_m2 < b->depth2_m2;
}

static int rnd_batch_before(const struct rnd_draw_batch *a, const struct rnd_draw_batch *b)
{
    return a->depth2_m2 < b->depth2_m2;
}

static int rnd_same_batch(const struct rnd_draw_entry *a, const struct rnd_draw_entry *b)
{
    return a->chain == b->chain && a->level == b->level && memcmp(a->color, b->color, sizeof a->color) == 0;
}

/* Entries first … first + count of the list (count at most r->list.cap) into batches of the same
 * chain, level and colour, nearest batch first (by its nearest member), each batch nearest first: a
 * fragment behind one already drawn fails the depth test before it is shaded, which on llvmpipe costs
 * about a quarter of a shaded one (docs/RESULTS.md, issue 32 seventh round: the auditorium's pixels
 * are covered 1.7× over); and one instanced draw replaces a draw per instance (about 5 µs each on
 * llvmpipe, calibrate's grid) for rows of identical chairs. Returns the number of batches; their
 * transforms are in r->list.transforms from each batch's slot. */
static size_t rnd_draw_batches(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view *v,
                               const uint32_t *index, const uint8_t *lod, const uint8_t *mask, unsigned layer_bit,
                               size_t first, size_t count)
{
    size_t n = 0;
    for (size_t k = first; k < first + count; ++k) {
        if (!rnd_entry_drawn(scene, index, lod, mask, layer_bit, k))
            continue;
        const struct scn_instance *in = &scene->instances[index[k]];
        double dx = in->position_m[0] - v->position_m[0], dy = in->position_m[1] - v->position_m[1],
               dz = in->position_m[2] - v->position_m[2];
        struct rnd_draw_entry *e = &r->list.entries[n++];
        *e = (struct rnd_draw_entry){(float)(dx * dx + dy * dy + dz * dz), (uint32_t)k, in->chain, lod[k], {0, 0, 0}};
        memcpy(e->color, in->color, sizeof e->color);
    }
    RND_SHELL_SORT(r->list.entries, n, struct rnd_draw_entry, rnd_entry_before);
    size_t batches = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i == 0 || !rnd_same_batch(&r->list.entries[i], &r->list.entries[i - 1]))
            r->list.batches[batches++] = (struct rnd_draw_batch){(uint32_t)i, 0, 0, r->list.entries[i].depth2_m2};
        r->list.batches[batches - 1].count++;
    }
    RND_SHELL_SORT(r->list.batches, batches, struct rnd_draw_batch, rnd_batch_before);
    uint32_t slot = 0; /* the transforms in the order the batches draw */
    for (size_t b = 0; b < batches; ++b) {
        struct rnd_draw_batch *bt = &r->list.batches[b];
        bt->slot = slot;
        for (uint32_t i = 0; i < bt->count; ++i, ++slot)
            rnd_model_view(&scene->instances[index[r->list.entries[bt->entry + i].k]], v, r->list.transforms + 16 * (size_t)slot);
    }
    return batches;
}

/* The shader's albedo terms for an instance, remade only when its colour changed since (the analysis
 * redraws one instance in several colours). */
static const struct rnd_albedo *rnd_instance_albedo(struct rnd_renderer *r, const struct scn_instance *in, uint32_t instance)
{
    struct rnd_albedo *a = &r->list.albedo[instance];
    if (memcmp(a->srgb, in->color, sizeof a->srgb) != 0) {
        for (int c = 0; c < 3; ++c) {
            double linear = rnd_srgb_decode(in->color[c]);
            a->srgb[c] = in->color[c];
            a->linear[c] = (float)linear;
            a->root[c] = (float)pow(linear, 1.0 / 2.4);
        }
    }
    return a;
}

uint64_t rnd_draw_view(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view *v,
                       const uint32_t *index, const uint8_t *lod, const uint8_t *mask, unsigned layer_bit,
                       size_t count, uint32_t *calls)
{
    float proj[16];
    for (int i = 0; i < 16; ++i)
        proj[i] = (float)v->projection[i];
    glUniformMatrix4fv(r->u_proj, 1, GL_FALSE, proj);
    hl_vec3d l = hl_q_rotate(hl_q_conj(v->orientation),
                             hl_v3_normalize(hl_v3(rnd_light_world[0], rnd_light_world[1], rnd_light_world[2])));
    glUniform3f(r->u_light, (float)l.x, (float)l.y, (float)l.z);
    glBindBuffer(GL_ARRAY_BUFFER, r->instance_vbo);
    uint64_t tris = 0;
    /* A list longer than the uploaded scene (repeated entries) goes in parts of what the arrays hold. */
    for (size_t first = 0; first < count && r->list.cap > 0; first += r->list.cap) {
        size_t part = count - first < r->list.cap ? count - first : r->list.cap;
        size_t batches = rnd_draw_batches(r, scene, v, index, lod, mask, layer_bit, first, part);
        if (batches == 0)
            continue;
        const struct rnd_draw_batch *last = &r->list.batches[batches - 1];
        /* Orphaned each view: fresh storage, so the driver need not wait for draws still reading the last. */
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(last->slot + last->count) * 16 * (GLsizeiptr)sizeof(float),
                     r->list.transforms, GL_STREAM_DRAW);
        for (size_t b = 0; b < batches; ++b) {
            const struct rnd_draw_batch *bt = &r->list.batches[b];
            const struct rnd_draw_entry *e = &r->list.entries[bt->entry];
            const struct scn_instance *in = &scene->instances[index[e->k]];
            const struct scn_lod *L = &scene->chains[in->chain].lods[e->level];
            const struct rnd_albedo *a = rnd_instance_albedo(r, in, index[e->k]);
            glUniform3fv(r->u_albedo, 1, a->linear);
            glUniform3fv(r->u_albedo_root, 1, a->root);
            glDrawElementsInstancedBaseInstance(GL_TRIANGLES, (GLsizei)L->index_count, GL_UNSIGNED_INT,
                                                (const void *)((uintptr_t)L->first_index * sizeof(uint32_t)),
                                                (GLsizei)bt->count, bt->slot);
            tris += (uint64_t)L->triangle_count * bt->count;
            ++*calls;
        }
    }
    return tris;
}
