/* Internal to render/: the work space of the image comparison, shared by analyze_image.c (which
 * compares) and analyze.c (which allocates it once per analysis and renders the images). */
#ifndef HMDLOD_RENDER_ANALYZE_INTERNAL_H
#define HMDLOD_RENDER_ANALYZE_INTERNAL_H

#include "render/render_internal.h"

/* Per component (indexed by its root label): pixel count, thickness at its thickest point and
 * longest chord, in pixels (analyze_image.c, rnd_measure_runs). */
struct rnd_component {
    uint32_t count;
    float narrow_px, long_px;
};

struct rnd_diff_work {
    int width_px, height_px;
    uint32_t *label;  /* width·height provisional labels, 0 = not differing */
    uint32_t *parent; /* union-find forest over labels */
    float *min_run_px; /* width·height: per pixel, its shortest run over the orientations */
    struct rnd_component *comp;
    uint32_t label_cap;
};
int rnd_diff_work_init(struct rnd_diff_work *w, int width_px, int height_px); /* −1: no memory */
void rnd_diff_work_free(struct rnd_diff_work *w);
/* rnd_image_compare on images of the work space's size, with no allocation. */
void rnd_diff_images(struct rnd_diff_work *w, const uint8_t *rgba_a, const uint8_t *rgba_b, double threshold_de,
                     int min_component_px, struct rnd_image_diff *out);

#endif
