/* Per-object viewing geometry (DESIGN.md "One frame", step 4): eccentricity, retinal velocity and
 * angular diameter, batched over the visible objects. */
#include "acuity/acuity.h"

#include <math.h>

/* |v| as sqrt(v·v): eye-relative distances (≤ 1e7 m) and image rates square far inside double's
 * range, and hypot (hl_v3_length, safe to 1e200) cost a quarter of a frame's viewing geometry. */
static inline double length(hl_vec3d v) { return sqrt(hl_v3_dot(v, v)); }

void acu_compute_geometry(const struct acu_viewer *viewer, const double *center_m, const double *radius_m,
                          const double *velocity_mps, const uint32_t *index, size_t count,
                          double *eccentricity_deg, double *retinal_velocity_degps,
                          double *angular_diameter_deg)
{
    const hl_vec3d omega = viewer->angular_velocity_radps;
    const double omega_degps = hl_v3_length(omega) * HL_DEG_PER_RAD;
    for (size_t k = 0; k < count; ++k) {
        uint32_t i = index[k];
        /* Eye-relative position in double first: at 1e6 m from the origin the difference of two
         * nearby positions still keeps sub-millimetre precision. */
        hl_vec3d rel = hl_v3_sub(hl_v3(center_m[3 * i], center_m[3 * i + 1], center_m[3 * i + 2]),
                                 viewer->eye_position_m);
        double dist = length(rel);
        double radius = radius_m[i];
        if (!(dist > radius)) {
            /* Eye inside the bounding sphere: the object surrounds the viewer. */
            eccentricity_deg[k] = 0.0;
            retinal_velocity_degps[k] = omega_degps;
            angular_diameter_deg[k] = 180.0;
            continue;
        }
        hl_vec3d d = hl_v3_scale(rel, 1.0 / dist);
        double half_angle_rad = asin(radius / dist);
        double centre_ecc_rad = hl_v3_angle_rad(viewer->gaze_dir, d);
        double ecc_rad = centre_ecc_rad - half_angle_rad;
        eccentricity_deg[k] = ecc_rad > 0.0 ? ecc_rad * HL_DEG_PER_RAD : 0.0;
        angular_diameter_deg[k] = 2.0 * half_angle_rad * HL_DEG_PER_RAD;

        /* Image motion on the retina: the direction d turns at (u⊥)/r from motion relative to the
         * eye, and the eye turns at ω (the gaze model's), so d moves on the retina at u⊥/r − ω × d. */
        hl_vec3d u = hl_v3_scale(viewer->linear_velocity_mps, -1.0);
        if (velocity_mps)
            u = hl_v3_add(u, hl_v3(velocity_mps[3 * i], velocity_mps[3 * i + 1], velocity_mps[3 * i + 2]));
        hl_vec3d u_perp = hl_v3_sub(u, hl_v3_scale(d, hl_v3_dot(u, d)));
        hl_vec3d rate = hl_v3_sub(hl_v3_scale(u_perp, 1.0 / dist), hl_v3_cross(omega, d));
        retinal_velocity_degps[k] = length(rate) * HL_DEG_PER_RAD;
    }
}
