/* Projected coverage for the frame (DESIGN.md step 6): every visible object's bounding sphere, and
 * for the few that claim a large share of the image, their oriented box as well — the smaller of
 * two upper bounds. A sphere that holds the eye claims the whole image: a room's floor, ceiling and
 * walls each do, so the auditorium's spheres claimed its views five times over and the cost model
 * predicted three times the measured frame (docs/RESULTS.md, "Cost-bounded selectors in replay"). */
#include "frame/select.h"

#include <string.h>

#include "acuity/acuity.h"
#include "scene/scene.h"

/* Objects whose sphere claims more than this share of all eyes' pixels get their box measured too
 * (about 1 µs each); below it a sphere's overstatement costs little. */
#define FRM_BOX_COVERAGE_SHARE 0.02

/* The instance's model-space box through its scale, rotation and position. */
static void instance_box(const struct scn_scene *scene, uint32_t inst, double centre[3], double axes[9])
{
    const struct scn_instance *in = &scene->instances[inst];
    const struct scn_chain *ch = &scene->chains[scene->chain_of_instance[inst]];
    hl_vec3d c = hl_v3(0.5 * (ch->box_min_m[0] + ch->box_max_m[0]), 0.5 * (ch->box_min_m[1] + ch->box_max_m[1]),
                       0.5 * (ch->box_min_m[2] + ch->box_max_m[2]));
    c = hl_v3_add(hl_v3(in->position_m[0], in->position_m[1], in->position_m[2]),
                  hl_q_rotate(in->rotation, hl_v3_scale(c, in->scale)));
    centre[0] = c.x, centre[1] = c.y, centre[2] = c.z;
    for (int k = 0; k < 3; ++k) {
        double half = 0.5 * (ch->box_max_m[k] - ch->box_min_m[k]) * in->scale;
        hl_vec3d a = hl_q_rotate(in->rotation, hl_v3(k == 0 ? half : 0, k == 1 ? half : 0, k == 2 ? half : 0));
        axes[3 * k] = a.x, axes[3 * k + 1] = a.y, axes[3 * k + 2] = a.z;
    }
}

void frm_coverage_compute(const struct scn_scene *scene, const struct acu_eye *eyes, int eye_count,
                          const uint32_t *visible, size_t count, double *pixels_px, uint8_t *boxed)
{
    acu_compute_pixels(eyes, eye_count, scene->center_m, scene->radius_m, visible, count, pixels_px);
    if (boxed)
        memset(boxed, 0, count);
    double image_px = 0.0;
    for (int e = 0; e < eye_count; ++e)
        image_px += eyes[e].width_px * eyes[e].height_px;
    for (size_t k = 0; k < count; ++k) {
        if (!(pixels_px[k] > FRM_BOX_COVERAGE_SHARE * image_px))
            continue;
        double centre[3], axes[9], box_px;
        instance_box(scene, visible[k], centre, axes);
        acu_compute_pixels_box(eyes, eye_count, centre, axes, 1, &box_px);
        if (box_px < pixels_px[k]) {
            pixels_px[k] = box_px;
            if (boxed)
                boxed[k] = 1;
        }
    }
}

double frm_level_cost_ms(const struct lod_cost_model *m, const struct scn_chain *ch, int level, double pixels_px,
                         int boxed)
{
    const struct scn_lod *lod = &ch->lods[level];
    double fragments_px = pixels_px * scn_lod_fill(ch, level, boxed);
    return lod_cost_object_ms(m, 2.0 * lod->triangle_count, 2.0 * lod->vertex_count, fragments_px, 2.0);
}

double frm_level_inset_cost_ms(const struct frm_inset_cost *m, const struct scn_chain *ch, int level,
                               double pixels_px, double inside_share, int boxed)
{
    const struct scn_lod *lod = &ch->lods[level];
    double fragments_px = pixels_px * scn_lod_fill(ch, level, boxed);
    return frm_inset_object_ms(m, 2.0 * lod->triangle_count, 2.0 * lod->vertex_count, fragments_px, 2.0, inside_share);
}
