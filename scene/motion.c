/* Motion paths: evaluation (closed form, so a replay at any frame rate sees the same poses and the
 * velocity is exact, not a finite difference), the JSON form, and a scene's motion set. */
#include "scene/scene.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void scn_motion_rigid(const struct scn_motion *m, double t_s, hl_vec3d default_pivot_m, struct scn_rigid *out)
{
    *out = (struct scn_rigid){.rotation = hl_q_identity(), .pivot_m = default_pivot_m};
    if (!m || !m->flags)
        return;
    if (m->flags & SCN_MOTION_SPIN) {
        double rate_radps = m->spin_rate_degps * HL_RAD_PER_DEG;
        /* fmod keeps the angle small over long sessions: sin/cos of 1e6 rad lose digits. */
        double angle_rad = fmod(rate_radps * t_s, 2.0 * HL_PI);
        out->rotation = hl_q_from_axis_angle(m->spin_axis, angle_rad);
        out->omega_radps = hl_v3_scale(m->spin_axis, rate_radps);
        if (m->spin_pivot_set)
            out->pivot_m = m->spin_pivot_m;
    }
    if (m->flags & SCN_MOTION_OSCILLATE) {
        double w = 2.0 * HL_PI / m->osc_period_s;
        double phase = w * fmod(t_s, m->osc_period_s) + m->osc_phase_deg * HL_RAD_PER_DEG;
        out->offset_m = hl_v3_scale(m->osc_direction, m->osc_amplitude_m * sin(phase));
        out->offset_velocity_mps = hl_v3_scale(m->osc_direction, m->osc_amplitude_m * w * cos(phase));
    }
    if ((m->flags & SCN_MOTION_KEYFRAMES) && m->key_count >= 2) {
        double period = m->key_t_s[m->key_count - 1];
        double u = fmod(t_s, period);
        if (u < 0)
            u += period;
        int k = 0; /* the segment [key k, key k+1] holding u; a time on a key starts the next segment */
        while (k + 2 < m->key_count && u >= m->key_t_s[k + 1])
            ++k;
        double dt = m->key_t_s[k + 1] - m->key_t_s[k];
        hl_vec3d d = hl_v3_sub(m->key_offset_m[k + 1], m->key_offset_m[k]);
        double f = (u - m->key_t_s[k]) / dt;
        out->offset_m = hl_v3_add(out->offset_m, hl_v3_add(m->key_offset_m[k], hl_v3_scale(d, f)));
        out->offset_velocity_mps = hl_v3_add(out->offset_velocity_mps, hl_v3_scale(d, 1.0 / dt));
    }
}

void scn_rigid_apply(const struct scn_rigid *r, hl_vec3d *position_m, hl_quatd *rotation, hl_vec3d *velocity_mps)
{
    /* d/dt [c + R(p − c) + o] = ω × R(p − c) + R ṗ + ȯ: the arm R(p − c) is local, so a scene far
     * from the origin keeps its precision (no ω × p with p ≈ 1e6 m). */
    hl_vec3d arm = hl_q_rotate(r->rotation, hl_v3_sub(*position_m, r->pivot_m));
    if (velocity_mps)
        *velocity_mps = hl_v3_add(hl_v3_add(hl_v3_cross(r->omega_radps, arm), hl_q_rotate(r->rotation, *velocity_mps)),
                                  r->offset_velocity_mps);
    *position_m = hl_v3_add(hl_v3_add(r->pivot_m, arm), r->offset_m);
    if (rotation)
        *rotation = hl_q_normalize(hl_q_mul(r->rotation, *rotation));
}

void scn_motion_eval(const struct scn_motion *m, double t_s, hl_vec3d base_position, hl_quatd base_rotation,
                     hl_vec3d *position, hl_quatd *rotation, hl_vec3d *velocity_mps)
{
    struct scn_rigid r;
    scn_motion_rigid(m, t_s, base_position, &r);
    hl_vec3d p = base_position, v = hl_v3(0, 0, 0);
    hl_quatd q = base_rotation;
    scn_rigid_apply(&r, &p, &q, &v);
    if (position)
        *position = p;
    if (rotation)
        *rotation = q;
    if (velocity_mps)
        *velocity_mps = v;
}

static int finite3(hl_vec3d v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

int scn_motion_check(const struct scn_motion *m, const char *where, struct hl_error *err)
{
    if (m->flags & ~(unsigned)(SCN_MOTION_SPIN | SCN_MOTION_OSCILLATE | SCN_MOTION_KEYFRAMES))
        return hl_fail(err, "%s: unknown motion flags 0x%x", where, m->flags);
    if (m->flags & SCN_MOTION_SPIN) {
        if (!finite3(m->spin_axis) || !(hl_v3_length(m->spin_axis) > 0))
            return hl_fail(err, "%s.spin.axis: must be a finite, non-zero vector", where);
        if (!isfinite(m->spin_rate_degps))
            return hl_fail(err, "%s.spin.rate_degps: must be finite", where);
        if (m->spin_pivot_set && !finite3(m->spin_pivot_m))
            return hl_fail(err, "%s.spin.pivot_m: must be finite", where);
    }
    if (m->flags & SCN_MOTION_OSCILLATE) {
        if (!finite3(m->osc_direction) || !(hl_v3_length(m->osc_direction) > 0))
            return hl_fail(err, "%s.oscillate.direction: must be a finite, non-zero vector", where);
        if (!(m->osc_amplitude_m >= 0) || !isfinite(m->osc_amplitude_m))
            return hl_fail(err, "%s.oscillate.amplitude_m: must be finite and >= 0", where);
        if (!(m->osc_period_s > 0) || !isfinite(m->osc_period_s))
            return hl_fail(err, "%s.oscillate.period_s: must be finite and > 0", where);
        if (!isfinite(m->osc_phase_deg))
            return hl_fail(err, "%s.oscillate.phase_deg: must be finite", where);
    }
    if (m->flags & SCN_MOTION_KEYFRAMES) {
        if (m->key_count < 2 || m->key_count > SCN_MOTION_MAX_KEYS)
            return hl_fail(err, "%s.keyframes: %d keys (2…%d)", where, m->key_count, SCN_MOTION_MAX_KEYS);
        if (m->key_t_s[0] != 0.0)
            return hl_fail(err, "%s.keyframes[0].t_s: the first key must be at 0 s", where);
        for (int k = 0; k < m->key_count; ++k) {
            if (!isfinite(m->key_t_s[k]) || (k > 0 && !(m->key_t_s[k] > m->key_t_s[k - 1])))
                return hl_fail(err, "%s.keyframes[%d].t_s: times must be finite and strictly increasing", where, k);
            if (!finite3(m->key_offset_m[k]))
                return hl_fail(err, "%s.keyframes[%d].offset_m: must be finite", where, k);
        }
    }
    return 0;
}

/* ---- JSON --------------------------------------------------------------------------------------- */

static int json_vec3(const cJSON *obj, const char *key, const char *where, int required, hl_vec3d *out,
                     int *found, struct hl_error *err)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (found)
        *found = v != NULL;
    if (!v)
        return required ? hl_fail(err, "%s.%s: missing", where, key) : 0;
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return hl_fail(err, "%s.%s: expected an array of 3 numbers", where, key);
    double c[3];
    for (int i = 0; i < 3; ++i) {
        const cJSON *e = cJSON_GetArrayItem(v, i);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return hl_fail(err, "%s.%s[%d]: expected a finite number", where, key, i);
        c[i] = e->valuedouble;
    }
    *out = hl_v3(c[0], c[1], c[2]);
    return 0;
}

static int json_number(const cJSON *obj, const char *key, const char *where, int required, double *out,
                       struct hl_error *err)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v)
        return required ? hl_fail(err, "%s.%s: missing", where, key) : 0;
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return hl_fail(err, "%s.%s: expected a finite number", where, key);
    *out = v->valuedouble;
    return 0;
}

/* Unknown members are errors, as in display profiles: a typo must not silently mean "still". */
static int json_only(const cJSON *obj, const char *const *known, const char *where, struct hl_error *err)
{
    if (!cJSON_IsObject(obj))
        return hl_fail(err, "%s: expected an object", where);
    for (const cJSON *c = obj->child; c; c = c->next) {
        int ok = 0;
        for (int k = 0; known[k] && !ok; ++k)
            ok = c->string && strcmp(c->string, known[k]) == 0;
        if (!ok)
            return hl_fail(err, "%s: unknown member '%s'", where, c->string ? c->string : "");
    }
    return 0;
}

int scn_motion_parse(const struct cJSON *node, const char *json_path, struct scn_motion *out, struct hl_error *err)
{
    static const char *const top[] = {"spin", "oscillate", "keyframes", NULL};
    static const char *const spin_keys[] = {"axis", "rate_degps", "pivot_m", NULL};
    static const char *const osc_keys[] = {"direction", "amplitude_m", "period_s", "phase_deg", NULL};
    static const char *const key_keys[] = {"t_s", "offset_m", NULL};
    const char *path = json_path ? json_path : "motion";
    struct scn_motion m = {0};
    *out = m;
    char where[512];
    if (json_only(node, top, path, err) != 0)
        return -1;
    const cJSON *spin = cJSON_GetObjectItemCaseSensitive(node, "spin");
    if (spin) {
        snprintf(where, sizeof where, "%s.spin", path);
        if (json_only(spin, spin_keys, where, err) || json_vec3(spin, "axis", where, 1, &m.spin_axis, NULL, err) ||
            json_number(spin, "rate_degps", where, 1, &m.spin_rate_degps, err) ||
            json_vec3(spin, "pivot_m", where, 0, &m.spin_pivot_m, &m.spin_pivot_set, err))
            return -1;
        m.flags |= SCN_MOTION_SPIN;
    }
    const cJSON *osc = cJSON_GetObjectItemCaseSensitive(node, "oscillate");
    if (osc) {
        snprintf(where, sizeof where, "%s.oscillate", path);
        if (json_only(osc, osc_keys, where, err) || json_vec3(osc, "direction", where, 1, &m.osc_direction, NULL, err) ||
            json_number(osc, "amplitude_m", where, 1, &m.osc_amplitude_m, err) ||
            json_number(osc, "period_s", where, 1, &m.osc_period_s, err) ||
            json_number(osc, "phase_deg", where, 0, &m.osc_phase_deg, err))
            return -1;
        m.flags |= SCN_MOTION_OSCILLATE;
    }
    const cJSON *keys = cJSON_GetObjectItemCaseSensitive(node, "keyframes");
    if (keys) {
        if (!cJSON_IsArray(keys))
            return hl_fail(err, "%s.keyframes: expected an array of {\"t_s\", \"offset_m\"} objects", path);
        int n = cJSON_GetArraySize(keys);
        if (n < 2 || n > SCN_MOTION_MAX_KEYS)
            return hl_fail(err, "%s.keyframes: %d keys (2…%d)", path, n, SCN_MOTION_MAX_KEYS);
        for (int k = 0; k < n; ++k) {
            const cJSON *key = cJSON_GetArrayItem(keys, k);
            snprintf(where, sizeof where, "%s.keyframes[%d]", path, k);
            if (json_only(key, key_keys, where, err) || json_number(key, "t_s", where, 1, &m.key_t_s[k], err) ||
                json_vec3(key, "offset_m", where, 1, &m.key_offset_m[k], NULL, err))
                return -1;
        }
        m.key_count = n;
        m.flags |= SCN_MOTION_KEYFRAMES;
    }
    if (scn_motion_check(&m, path, err) != 0)
        return -1;
    if (m.flags & SCN_MOTION_SPIN)
        m.spin_axis = hl_v3_normalize(m.spin_axis);
    if (m.flags & SCN_MOTION_OSCILLATE)
        m.osc_direction = hl_v3_normalize(m.osc_direction);
    *out = m;
    return 0;
}

/* ---- a scene's motion set ------------------------------------------------------------------------- */

void scn_motion_set_free(struct scn_motion_set *set)
{
    if (!set)
        return;
    free(set->instance_motion);
    free(set->group_motion);
    free(set->rest_position_m);
    free(set->rest_rotation);
    free(set->rest_group_center_m);
    free(set->rest_group_radius_m);
    free(set->group_of_instance);
    free(set->velocity_mps);
    free(set->group_rigid);
    free(set->group_rotation);
    free(set->group_frame);
    free(set);
}

int scn_scene_motion_create(struct scn_scene *s, struct hl_error *err)
{
    uint32_t n = s->instance_count, g = s->group_count;
    scn_motion_set_free(s->motion);
    struct scn_motion_set *set = s->motion = calloc(1, sizeof *set);
    if (!set)
        return hl_fail(err, "scene %s: out of memory for motion", s->name);
    set->instance_motion = calloc(n ? n : 1, sizeof *set->instance_motion);
    set->group_motion = calloc(g ? g : 1, sizeof *set->group_motion);
    set->rest_position_m = calloc(n ? n : 1, sizeof *set->rest_position_m);
    set->rest_rotation = calloc(n ? n : 1, sizeof *set->rest_rotation);
    set->rest_group_center_m = calloc(g ? 3 * (size_t)g : 1, sizeof(double));
    set->rest_group_radius_m = calloc(g ? g : 1, sizeof(double));
    set->group_of_instance = malloc((n ? n : 1) * sizeof *set->group_of_instance);
    set->velocity_mps = calloc(n ? 3 * (size_t)n : 1, sizeof(double));
    set->group_rigid = calloc(g ? g : 1, sizeof *set->group_rigid);
    set->group_rotation = calloc(g ? g : 1, sizeof *set->group_rotation);
    set->group_frame = calloc(g ? g : 1, sizeof *set->group_frame);
    if (!set->instance_motion || !set->group_motion || !set->rest_position_m || !set->rest_rotation ||
        !set->rest_group_center_m || !set->rest_group_radius_m || !set->group_of_instance || !set->velocity_mps ||
        !set->group_rigid || !set->group_rotation || !set->group_frame) {
        scn_motion_set_free(set);
        s->motion = NULL;
        return hl_fail(err, "scene %s: out of memory for motion", s->name);
    }
    for (uint32_t i = 0; i < n; ++i) {
        const struct scn_instance *in = &s->instances[i];
        set->rest_position_m[i] = hl_v3(in->position_m[0], in->position_m[1], in->position_m[2]);
        set->rest_rotation[i] = in->rotation;
        set->group_of_instance[i] = SCN_NONE;
    }
    for (uint32_t k = 0; k < g; ++k) {
        const struct scn_group *gr = &s->groups[k];
        memcpy(set->rest_group_center_m + 3 * (size_t)k, gr->center_m, sizeof gr->center_m);
        set->rest_group_radius_m[k] = gr->radius_m;
        set->group_rotation[k] = hl_q_identity();
        for (uint32_t j = 0; j < gr->instance_count; ++j) {
            uint32_t i = s->group_instances[gr->first_instance + j];
            if (i >= n || set->group_of_instance[i] != SCN_NONE) {
                scn_motion_set_free(set);
                s->motion = NULL;
                return hl_fail(err, "scene %s: group %s: instance %u %s", s->name, gr->name, i,
                               i >= n ? "does not exist" : "is already in another group");
            }
            set->group_of_instance[i] = k;
        }
    }
    return 0;
}
