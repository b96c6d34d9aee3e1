/* Projected coverage of oriented boxes (acuity.h): for the large objects whose bounding sphere
 * overstates what they fill — a room's floor and walls each hold the viewer inside their sphere,
 * which then claims the whole image, although together they fill it about once. The box is clipped
 * to the space in front of the eye, its outline (a convex polygon: the hull of the projected
 * corners and edge crossings) clipped to the image, and its area taken exactly. */
#include <math.h>
#include <stdlib.h>

#include "acuity/acuity.h"

/* Points nearer the eye plane than this project too far to matter: they are clipped to the image. */
#define BOX_NEAR_M 1e-4

struct pt {
    double x, y;
};

static double cross3(struct pt o, struct pt a, struct pt b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

static int pt_less(const void *pa, const void *pb)
{
    const struct pt *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    return (a->y > b->y) - (a->y < b->y);
}

/* Andrew's monotone chain: the convex hull of n ≤ 20 points, counter-clockwise, into hull (room for
 * n + 1). Returns its vertex count. */
static int convex_hull(struct pt *p, int n, struct pt *hull)
{
    qsort(p, (size_t)n, sizeof *p, pt_less);
    int k = 0;
    for (int i = 0; i < n; ++i) {
        while (k >= 2 && cross3(hull[k - 2], hull[k - 1], p[i]) <= 0.0)
            --k;
        hull[k++] = p[i];
    }
    for (int i = n - 2, lower = k + 1; i >= 0; --i) {
        while (k >= lower && cross3(hull[k - 2], hull[k - 1], p[i]) <= 0.0)
            --k;
        hull[k++] = p[i];
    }
    return k > 1 ? k - 1 : k;
}

/* Sutherland–Hodgman against one side of the image: keeps s·coord ≤ s·limit (axis 0 = x, 1 = y). */
static int clip_side(const struct pt *in, int n, struct pt *out, int axis, double limit, double s)
{
    int m = 0;
    for (int i = 0; i < n; ++i) {
        struct pt a = in[i], b = in[(i + 1) % n];
        double da = s * ((axis ? a.y : a.x) - limit), db = s * ((axis ? b.y : b.x) - limit);
        if (da <= 0.0)
            out[m++] = a;
        if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
            double t = da / (da - db);
            out[m++] = (struct pt){a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        }
    }
    return m;
}

static double polygon_area(const struct pt *p, int n)
{
    double a = 0.0;
    for (int i = 0; i < n; ++i)
        a += p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y;
    return 0.5 * fabs(a);
}

/* One box in one eye, in pixels. */
static double box_eye_pixels(const struct acu_eye *e, const double *c, const double *axes)
{
    hl_quatd to_eye = hl_q_conj(e->orientation);
    hl_vec3d centre = hl_q_rotate(to_eye, hl_v3_sub(hl_v3(c[0], c[1], c[2]), e->position_m));
    hl_vec3d ax[3];
    for (int k = 0; k < 3; ++k)
        ax[k] = hl_q_rotate(to_eye, hl_v3(axes[3 * k], axes[3 * k + 1], axes[3 * k + 2]));
    hl_vec3d corner[8];
    for (int k = 0; k < 8; ++k) {
        hl_vec3d p = centre;
        for (int a = 0; a < 3; ++a)
            p = hl_v3_add(p, hl_v3_scale(ax[a], (k >> a) & 1 ? 1.0 : -1.0));
        corner[k] = p;
    }
    /* The clipped box's vertices: corners in front, and where the 12 edges cross the near plane. */
    struct pt pts[20];
    int n = 0;
    for (int k = 0; k < 8; ++k) {
        double z = -corner[k].z;
        if (z >= BOX_NEAR_M)
            pts[n++] = (struct pt){corner[k].x / z, corner[k].y / z};
        for (int a = 0; a < 3; ++a) {
            int j = k | (1 << a);
            if (j == k)
                continue; /* each edge once: from the corner with bit a clear */
            double zj = -corner[j].z;
            if ((z < BOX_NEAR_M) != (zj < BOX_NEAR_M)) {
                double t = (BOX_NEAR_M - z) / (zj - z);
                hl_vec3d q = hl_v3_add(corner[k], hl_v3_scale(hl_v3_sub(corner[j], corner[k]), t));
                pts[n++] = (struct pt){q.x / BOX_NEAR_M, q.y / BOX_NEAR_M};
            }
        }
    }
    if (n < 3)
        return 0.0;
    struct pt hull[41], a[48], b[48]; /* the chain may hold 2n points on its way */
    int m = convex_hull(pts, n, hull);
    m = clip_side(hull, m, a, 0, e->tan_right, 1.0);
    m = clip_side(a, m, b, 0, -e->tan_left, -1.0);
    m = clip_side(b, m, a, 1, e->tan_up, 1.0);
    m = clip_side(a, m, b, 1, -e->tan_down, -1.0);
    if (m < 3)
        return 0.0;
    double px_per_tan2 = e->width_px / (e->tan_left + e->tan_right) * (e->height_px / (e->tan_up + e->tan_down));
    double area = polygon_area(b, m) * px_per_tan2, image_px = e->width_px * e->height_px;
    return area < image_px ? area : image_px;
}

void acu_compute_pixels_box(const struct acu_eye *eyes, int eye_count, const double *box_center_m,
                            const double *box_axes_m, size_t count, double *pixels_px)
{
    int n_eyes = eye_count < 4 ? eye_count : 4;
    for (size_t k = 0; k < count; ++k) {
        double sum = 0.0;
        for (int e = 0; e < n_eyes; ++e)
            sum += box_eye_pixels(&eyes[e], &box_center_m[3 * k], &box_axes_m[9 * k]);
        pixels_px[k] = sum;
    }
}
