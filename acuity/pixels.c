/* Projected coverage of bounding spheres (acuity.h): the pixels an object fills, which both the cost
 * model (fill) and Funkhouser's benefit (Size, 1993 §5) need, per eye and summed. */
#include <math.h>

#include "acuity/acuity.h"

/* An eye with its world-to-eye rotation as a matrix: one matrix product per object instead of two
 * quaternion products. */
struct eye_frame {
    const struct acu_eye *e;
    double r[3][3];
};

static void eye_frame_init(struct eye_frame *f, const struct acu_eye *e)
{
    f->e = e;
    hl_quatd q = hl_q_conj(e->orientation);
    hl_vec3d axes[3] = {hl_q_rotate(q, hl_v3(1, 0, 0)), hl_q_rotate(q, hl_v3(0, 1, 0)), hl_q_rotate(q, hl_v3(0, 0, 1))};
    for (int c = 0; c < 3; ++c) {
        f->r[0][c] = axes[c].x;
        f->r[1][c] = axes[c].y;
        f->r[2][c] = axes[c].z;
    }
}

static inline double max2(double a, double b) { return a > b ? a : b; }
static inline double min2(double a, double b) { return a < b ? a : b; }

/* The silhouette's extent along one image axis, in tangents: the planes through the eye that contain
 * the other image axis and touch the sphere. In the plane of this axis and the view direction the
 * sphere is a circle of radius r at (a, z) (z forward), seen under the angles φ ± β with tan φ = a/z and
 * sin β = r/√(a² + z²). Clipped to the image [−tan_neg, tan_pos]; 0 when it misses it. */
static int axis_extent(double a, double z, double r, double tan_neg, double tan_pos, double *lo, double *hi,
                       double *kept)
{
    double h2 = a * a + z * z - r * r;
    if (h2 <= 0.0) { /* the eye is level with the sphere along this axis: it spans the axis */
        *lo = -tan_neg, *hi = tan_pos, *kept = 0.0;
        return 1;
    }
    double l, h;
    if (z > 0.0) {
        double t = a / z, b = r / sqrt(h2); /* tan(φ ± β) without trigonometry */
        double den_hi = 1.0 - t * b, den_lo = 1.0 + t * b;
        h = den_hi > 0.0 ? (t + b) / den_hi : INFINITY;
        l = den_lo > 0.0 ? (t - b) / den_lo : -INFINITY;
    } else { /* the centre is level with or behind the eye: in angles, since tangents wrap */
        double phi = atan2(a, z), beta = asin(r / sqrt(a * a + z * z));
        double lo_ang = max2(phi - beta, -atan(tan_neg)), hi_ang = min2(phi + beta, atan(tan_pos));
        if (hi_ang <= lo_ang)
            return 0;
        l = tan(lo_ang), h = tan(hi_ang);
        *kept = 0.0; /* the silhouette reaches behind the eye: unbounded */
        *lo = max2(l, -tan_neg), *hi = min2(h, tan_pos);
        return *hi > *lo;
    }
    *lo = max2(l, -tan_neg);
    *hi = min2(h, tan_pos);
    *kept = isfinite(h - l) && h > l ? (*hi - *lo) / (h - l) : 0.0;
    return *hi > *lo;
}

/* One eye: the bounding box of the silhouette (exact along both image axes), weighted π/4 (an
 * ellipse fills π/4 of its box when aligned with it, less otherwise) when the image holds the whole
 * box, rising to 1 as the image clips it (a large silhouette's clipped part fills nearly all of
 * what is left): coverage is over-counted at times, never under-counted in the tests. */
static double eye_pixels(const struct eye_frame *f, const double *c, double r)
{
    const struct acu_eye *e = f->e;
    double rx = c[0] - e->position_m.x, ry = c[1] - e->position_m.y, rz = c[2] - e->position_m.z;
    double dx = f->r[0][0] * rx + f->r[0][1] * ry + f->r[0][2] * rz; /* eye frame: −Z forward */
    double dy = f->r[1][0] * rx + f->r[1][1] * ry + f->r[1][2] * rz;
    double dz = f->r[2][0] * rx + f->r[2][1] * ry + f->r[2][2] * rz;
    double image_px = e->width_px * e->height_px;
    if (dx * dx + dy * dy + dz * dz <= r * r)
        return image_px; /* the eye is inside the sphere */
    double z = -dz;
    if (z + r <= 0.0)
        return 0.0; /* wholly behind */
    double x0, x1, y0, y1, kept_x, kept_y;
    if (!axis_extent(dx, z, r, e->tan_left, e->tan_right, &x0, &x1, &kept_x) ||
        !axis_extent(dy, z, r, e->tan_down, e->tan_up, &y0, &y1, &kept_y))
        return 0.0;
    double px_per_tan_x = e->width_px / (e->tan_left + e->tan_right);
    double px_per_tan_y = e->height_px / (e->tan_up + e->tan_down);
    double fill = HL_PI / 4.0 + (1.0 - HL_PI / 4.0) * (1.0 - kept_x * kept_y);
    double area = (x1 - x0) * px_per_tan_x * (y1 - y0) * px_per_tan_y * fill;
    return min2(area, image_px);
}

void acu_compute_pixels(const struct acu_eye *eyes, int eye_count, const double *center_m,
                        const double *radius_m, const uint32_t *index, size_t count, double *pixels_px)
{
    struct eye_frame frames[4];
    int n_eyes = eye_count < 4 ? eye_count : 4;
    for (int e = 0; e < n_eyes; ++e)
        eye_frame_init(&frames[e], &eyes[e]);
    for (size_t k = 0; k < count; ++k) {
        uint32_t i = index[k];
        double sum = 0.0;
        for (int e = 0; e < n_eyes; ++e)
            sum += eye_pixels(&frames[e], &center_m[3 * (size_t)i], radius_m[i]);
        pixels_px[k] = sum;
    }
}
