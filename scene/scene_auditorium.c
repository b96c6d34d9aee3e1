/* "auditorium": the test model of Funkhouser & Séquin (1993 §7) — rows of chairs, each a chain of
 * LODs, plus a stage and the room. The viewer sits among the seats at the origin, head 1.2 m above
 * the floor, facing the stage along −Z; rows in front and behind make head turns change the load. */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>

enum { AUD_ROWS = 10, AUD_SEATS = 15, AUD_VIEWER_ROW = 6, AUD_VIEWER_SEAT = 7 };

static const double aud_floor_y = -1.2;     /* the viewer's eyes are 1.2 m above the floor */
static const double aud_row_pitch = 1.0, aud_seat_pitch = 0.6;

/* Chair, centred on its model origin (so the bounding-sphere centre is the instance position):
 * seat top 0.45 m above the floor, back up to 0.9 m; it spans y ∈ [−0.45, 0.45]. */
static void aud_chair(struct scn_mesh *m, int level)
{
    const hl_quatd id = hl_q_identity();
    const double fy = -0.45, seat_y = fy + 0.43, leg_h = 0.41;
    hl_vec3d seat_c = hl_v3(0, seat_y, 0), seat_h = hl_v3(0.24, 0.025, 0.22);
    hl_vec3d back_c = hl_v3(0, 0.22, 0.20), back_h = hl_v3(0.22, 0.16, 0.02);
    switch (level) {
    case 0: /* 600 triangles: round legs, back posts and arm rails (the cylinders carry the detail) */
    case 1: { /* 208: the same parts, coarser cylinders, box arm rails */
        int leg_seg = level == 0 ? 20 : 7, post_seg = level == 0 ? 16 : 6;
        for (int i = 0; i < 4; ++i) {
            double x = (i & 1) ? 0.21 : -0.21, z = (i & 2) ? 0.19 : -0.19;
            scn_mesh_add_cylinder(m, hl_v3(x, fy + leg_h / 2, z), 0.022, leg_h / 2, leg_seg, id);
        }
        scn_mesh_add_box(m, seat_c, seat_h, id);
        scn_mesh_add_box(m, back_c, back_h, id);
        for (int i = 0; i < 2; ++i) {
            double x = i ? 0.21 : -0.21;
            scn_mesh_add_cylinder(m, hl_v3(x, 0.12, 0.20), 0.018, 0.33 / 2 + 0.07, post_seg, id);
            if (level == 0) /* arm rails along z at 0.2 m above the seat */
                scn_mesh_add_cylinder(m, hl_v3(x + (i ? 0.03 : -0.03), seat_y + 0.2, 0.0), 0.02, 0.19, 16,
                                      hl_q_from_axis_angle(hl_v3(1, 0, 0), HL_PI / 2));
            else
                scn_mesh_add_box(m, hl_v3(x + (i ? 0.03 : -0.03), seat_y + 0.2, 0.0), hl_v3(0.02, 0.02, 0.19), id);
        }
        break;
    }
    case 2: /* 60: seat, back, and the legs/arms merged into two side panels and a back post bar */
        scn_mesh_add_box(m, seat_c, seat_h, id);
        scn_mesh_add_box(m, back_c, back_h, id);
        for (int i = 0; i < 2; ++i)
            scn_mesh_add_box(m, hl_v3(i ? 0.225 : -0.225, fy + 0.31, 0.0), hl_v3(0.015, 0.31, 0.21), id);
        scn_mesh_add_box(m, hl_v3(0, seat_y - 0.2, 0.19), hl_v3(0.21, 0.02, 0.02), id);
        break;
    default: /* 12: one box, the chair's silhouette as seen from a distance */
        scn_mesh_add_box(m, hl_v3(0, fy + 0.45, 0.02), hl_v3(0.24, 0.45, 0.2), id);
        break;
    }
}

int scn_auditorium_add_chair_chain(struct scn_scene *s, const char *name, struct hl_error *err)
{
    struct scn_mesh chair[4] = {{0}};
    for (int l = 0; l < 4; ++l)
        aud_chair(&chair[l], l);
    int rc = scn_scene_add_chain(s, name, chair, 4, err);
    for (int l = 0; l < 4; ++l)
        scn_mesh_free(&chair[l]);
    return rc;
}

/* The hierarchy (Funkhouser & Séquin 1993 §7 treat each row as a unit; Mason & Blake 1997 §2):
 * "seating" holds the rows, each row its two halves either side of the viewer's seat (seats 0…6 and
 * 7…14), and "room" the walls, floor, ceiling and stage. A whole row always reaches the viewer, who
 * sits among the rows, so only halves can fall wholly outside the view. Groups: 0 seating, 1 room,
 * 2… the rows, then the halves (row r: 2 + AUD_ROWS + 2r, +1). Instance order is unchanged (chairs
 * row by row, then the surfaces). */
static int aud_build_groups(struct scn_scene *s, uint32_t nsurf, struct hl_error *err)
{
    const uint32_t ng = 2 + 3 * AUD_ROWS, first_half = 2 + AUD_ROWS, left_seats = AUD_VIEWER_SEAT;
    s->groups = calloc(ng, sizeof *s->groups);
    s->group_children = calloc(3 * AUD_ROWS, sizeof *s->group_children);
    s->group_instances = calloc(s->instance_count, sizeof *s->group_instances);
    if (!s->groups || !s->group_children || !s->group_instances)
        return hl_fail(err, "scene auditorium: out of memory for groups");
    s->group_count = ng;
    for (uint32_t g = 0; g < ng; ++g)
        s->groups[g] = (struct scn_group){.parent = g < 2 ? SCN_NONE : g < first_half ? 0 : 2 + (g - first_half) / 2,
                                          .impostor_chain = SCN_NONE, .impostor_instance = SCN_NONE, .importance = 1.0};
    snprintf(s->groups[0].name, SCN_NAME_MAX, "seating");
    s->groups[0].first_child = 0;
    s->groups[0].child_count = AUD_ROWS;
    snprintf(s->groups[1].name, SCN_NAME_MAX, "room");
    s->groups[1].first_instance = AUD_ROWS * AUD_SEATS;
    s->groups[1].instance_count = nsurf;
    for (uint32_t r = 0; r < AUD_ROWS; ++r) {
        struct scn_group *row = &s->groups[2 + r];
        snprintf(row->name, SCN_NAME_MAX, "row%u", r);
        row->first_child = AUD_ROWS + 2 * r;
        row->child_count = 2;
        s->group_children[r] = 2 + r;
        for (uint32_t h = 0; h < 2; ++h) {
            uint32_t g = first_half + 2 * r + h;
            struct scn_group *half = &s->groups[g];
            snprintf(half->name, SCN_NAME_MAX, "row%u_%s", r, h ? "right" : "left");
            half->first_instance = r * AUD_SEATS + (h ? left_seats : 0);
            half->instance_count = h ? AUD_SEATS - left_seats : left_seats;
            s->group_children[AUD_ROWS + 2 * r + h] = g;
        }
    }
    for (uint32_t i = 0; i < s->instance_count; ++i)
        s->group_instances[i] = i;
    scn_scene_group_bounds(s);
    return scn_scene_check_groups(s, err);
}

struct aud_surface {
    const char *name;
    hl_vec3d center, half;
    float color[3];
};

int scn_scene_build_auditorium(const struct scn_scene_params *p, struct scn_scene *s, struct hl_error *err)
{
    snprintf(s->name, sizeof s->name, "auditorium");
    int rc = scn_auditorium_add_chair_chain(s, "chair", err);
    if (rc != 0)
        return -1;

    /* The room is built from solid boxes just outside it, so their outward faces look inward and
     * back-face culling needs no exception: floor, ceiling, side walls, end walls and the stage. */
    const double fy = aud_floor_y, top = fy + 6.0, xw = 7.0, zf = -14.0, zb = 6.0;
    const struct aud_surface surf[] = {
        {"floor", hl_v3(0, fy - 0.1, (zf + zb) / 2), hl_v3(xw, 0.1, (zb - zf) / 2), {0.32f, 0.24f, 0.20f}},
        {"ceiling", hl_v3(0, top + 0.1, (zf + zb) / 2), hl_v3(xw, 0.1, (zb - zf) / 2), {0.80f, 0.80f, 0.78f}},
        {"wall_left", hl_v3(-xw - 0.1, (fy + top) / 2, (zf + zb) / 2), hl_v3(0.1, (top - fy) / 2, (zb - zf) / 2), {0.62f, 0.55f, 0.48f}},
        {"wall_right", hl_v3(xw + 0.1, (fy + top) / 2, (zf + zb) / 2), hl_v3(0.1, (top - fy) / 2, (zb - zf) / 2), {0.62f, 0.55f, 0.48f}},
        {"wall_front", hl_v3(0, (fy + top) / 2, zf - 0.1), hl_v3(xw, (top - fy) / 2, 0.1), {0.45f, 0.20f, 0.22f}},
        {"wall_back", hl_v3(0, (fy + top) / 2, zb + 0.1), hl_v3(xw, (top - fy) / 2, 0.1), {0.62f, 0.55f, 0.48f}},
        {"stage", hl_v3(0, fy + 0.5, -10.5), hl_v3(6.0, 0.5, 2.5), {0.55f, 0.38f, 0.22f}},
    };
    const uint32_t nsurf = sizeof surf / sizeof surf[0];
    for (uint32_t i = 0; i < nsurf; ++i) { /* each surface is its own one-level chain at its origin */
        struct scn_mesh box = {0};
        scn_mesh_add_box(&box, hl_v3(0, 0, 0), surf[i].half, hl_q_identity());
        rc = scn_scene_add_chain(s, surf[i].name, &box, 1, err);
        scn_mesh_free(&box);
        if (rc != 0)
            return -1;
    }

    uint32_t n = AUD_ROWS * AUD_SEATS + nsurf;
    if (scn_scene_alloc_instances(s, n, err) != 0)
        return -1;
    /* Seats face the stage (−Z): the chair's back is at +z in its model frame, so no rotation. A
     * small seeded jitter keeps rows from looking machine-placed and makes the seed matter. */
    struct scn_rng g = {p->seed};
    static const float seat_colors[2][3] = {{0.60f, 0.12f, 0.14f}, {0.52f, 0.10f, 0.12f}};
    uint32_t k = 0;
    for (int row = 0; row < AUD_ROWS; ++row) {
        for (int seat = 0; seat < AUD_SEATS; ++seat) {
            double jx = 0.02 * (scn_rng_uniform(&g) - 0.5), yaw = 0.06 * (scn_rng_uniform(&g) - 0.5);
            /* The viewer's own seat: eyes above the seat at the origin, the chair 0.15 m behind. */
            double x = (seat - AUD_VIEWER_SEAT) * aud_seat_pitch + jx;
            double z = (row - AUD_VIEWER_ROW) * aud_row_pitch + 0.15;
            scn_scene_set_instance(s, k++, 0, hl_v3(x, fy + 0.45, z), hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw),
                                   1.0, seat_colors[(row + seat) & 1]);
        }
    }
    for (uint32_t i = 0; i < nsurf; ++i)
        scn_scene_set_instance(s, k++, 1 + i, surf[i].center, hl_q_identity(), 1.0, surf[i].color);
    return aud_build_groups(s, nsurf, err);
}
