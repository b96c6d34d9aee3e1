/* Fuzz target: head-motion trace text (replay/trace_parse.c, trace_edvam.c) through rpl_trace_parse,
 * the in-memory entry point rpl_trace_load uses. The first byte picks a header put before the rest,
 * so every format's row parser is reached without the fuzzer having to spell its header: 0 none
 * (the bytes as they are: any header, or Nasrabadi's headerless rows), 1 the project's CSV with
 * position and gaze, 2 Corbillon MMSys'18, 3 the EDVAM eye-tracker log. A parsed trace is sampled
 * (rpl_trace_sample) before, inside and after its span: the poses must be finite and unit. */
#include "fuzz_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "replay/replay.h"

static const char *const headers[4] = {
    "",
    "t_s,qw,qx,qy,qz,px,py,pz,gx,gy,gz\n",
    "timestamp viewpoint w x y z\n",
    "index,time,L_x,L_y,L_z,C_x,C_y,C_z,F_x,F_y,F_z,confidence,gaze_norm_pos_x,gaze_norm_pos_y,"
    "norm_pos_x,norm_pos_y,diameter,ellipse_center_x,ellipse_center_y,ellipse_axis_a,"
    "ellipse_axis_b,ellipse_angle,diameter_3d,model_confidence,model_id,sphere_center_x,"
    "sphere_center_y,sphere_center_z,sphere_radius,circle_3d_center_x,circle_3d_center_y,"
    "circle_3d_center_z,circle_3d_normal_x,circle_3d_normal_y,circle_3d_normal_z,"
    "circle_3d_radius,theta,phi,projected_sphere_center_x,projected_sphere_center_y,"
    "projected_sphere_axis_a,projected_sphere_axis_b,index,time\n",
};

static void check_pose(const struct trk_pose *p)
{
    const hl_quatd *q = &p->orientation;
    double n = q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z;
    FUZZ_CHECK(isfinite(n) && fabs(n - 1.0) < 1e-6, "sampled orientation not finite and unit");
    FUZZ_CHECK(isfinite(p->angular_velocity_radps.x) && isfinite(p->angular_velocity_radps.y) &&
                   isfinite(p->angular_velocity_radps.z),
               "sampled angular velocity not finite");
    FUZZ_CHECK(isfinite(p->position_m.x) && isfinite(p->position_m.y) && isfinite(p->position_m.z),
               "sampled position not finite");
    FUZZ_CHECK(isfinite(p->gaze_dir_head.x) && isfinite(p->gaze_dir_head.y) && isfinite(p->gaze_dir_head.z),
               "sampled gaze not finite");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    const char *header = headers[data[0] % 4];
    size_t hn = strlen(header), n = hn + size - 1;
    char *text = malloc(n ? n : 1);
    if (!text)
        return 0;
    memcpy(text, header, hn);
    memcpy(text + hn, data + 1, size - 1);
    struct rpl_trace t;
    struct hl_error err;
    if (rpl_trace_parse(text, n, "fuzz.csv", &t, &err) == 0) {
        FUZZ_CHECK(t.count > 0, "a parsed trace without samples");
        for (size_t i = 1; i < t.count; ++i)
            FUZZ_CHECK(t.time_s[i] > t.time_s[i - 1], "trace times not strictly increasing");
        double t0 = t.time_s[0], t1 = t.time_s[t.count - 1];
        const double at[] = {t0 - 1.0, t0, 0.5 * (t0 + t1), t1, t1 + 1.0, t0 + 0.25 * (t1 - t0)};
        for (size_t i = 0; i < sizeof at / sizeof at[0]; ++i) {
            struct trk_pose pose;
            rpl_trace_sample(&t, at[i], &pose);
            check_pose(&pose);
        }
        char line[512];
        rpl_trace_report_format(&t.report, line, sizeof line);
        rpl_trace_free(&t);
    }
    free(text);
    return 0;
}
