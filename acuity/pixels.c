/* Projected coverage of bounding spheres (acuity.h): the pixels an object fills, which both the cost
 * model (fill) and Funkhouser's benefit (Size, 1993 §5) need, per eye and summed. */
#include <math.h>

#include "acuity/acuity.h"

/* One eye. The sphere's silhouette is the disc of its tangent cone: on the view axis its radius in
 * the image's tangent plane is r / √(d² − r²); off axis the projection is an ellipse stretched along
 * the radial direction by about d / z, which the bounding square takes as its half side. A sphere
 * reaching behind the eye's plane (z ≤ r) projects without bound, so it is taken to fill the image:
 * over-predicting cost is safe, under-predicting breaks the budget. */
static double eye_pixels(const struct acu_eye *e, const double *c, double r)
{
    hl_vec3d rel = hl_v3(c[0] - e->position_m.x, c[1] - e->position_m.y, c[2] - e->position_m.z);
    hl_vec3d d = hl_q_rotate(hl_q_conj(e->orientation), rel); /* eye frame: −Z forward */
    double dist2 = hl_v3_dot(d, d);
    double z = -d.z;
    double image_px = e->width_px * e->height_px;
    if (dist2 <= r * r)
        return image_px; /* the eye is inside the sphere */
    if (z + r <= 0.0)
        return 0.0; /* wholly behind */
    if (z <= r)
        return image_px;
    double half_tan = r / sqrt(dist2 - r * r) * (sqrt(dist2) / z);
    double x = d.x / z, y = d.y / z;
    double x0 = fmax(x - half_tan, -e->tan_left), x1 = fmin(x + half_tan, e->tan_right);
    double y0 = fmax(y - half_tan, -e->tan_down), y1 = fmin(y + half_tan, e->tan_up);
    if (x1 <= x0 || y1 <= y0)
        return 0.0;
    double px_per_tan_x = e->width_px / (e->tan_left + e->tan_right);
    double px_per_tan_y = e->height_px / (e->tan_up + e->tan_down);
    double area = (x1 - x0) * px_per_tan_x * (y1 - y0) * px_per_tan_y * (HL_PI / 4.0);
    return fmin(area, image_px);
}

void acu_compute_pixels(const struct acu_eye *eyes, int eye_count, const double *center_m,
                        const double *radius_m, const uint32_t *index, size_t count, double *pixels_px)
{
    for (size_t k = 0; k < count; ++k) {
        uint32_t i = index[k];
        double sum = 0.0;
        for (int e = 0; e < eye_count; ++e)
            sum += eye_pixels(&eyes[e], &center_m[3 * (size_t)i], radius_m[i]);
        pixels_px[k] = sum;
    }
}
