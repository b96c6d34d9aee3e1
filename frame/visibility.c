/* What decides that lost detail is invisible (docs/visibility.md): Reddy's acuity H(v, E) at full
 * contrast, or the contrast sensitivity function applied to each lost band's measured contrast at
 * the eye's adapting luminance. This file holds the session's choice and the per-frame table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"

static const char *const criterion_names[] = {"contrast", "acuity"};

int frm_visibility_options(const struct frm_options *o, enum frm_visibility_criterion *criterion,
                           enum acu_csf_model *csf, struct hl_error *err)
{
    const char *name = o->visibility ? o->visibility : "contrast";
    int k = 0;
    while (k < 2 && strcmp(name, criterion_names[k]) != 0)
        ++k;
    if (k == 2)
        return hl_fail(err, "--visibility: unknown criterion '%s' (known: contrast, acuity)", name);
    *criterion = (enum frm_visibility_criterion)k;
    if (acu_csf_model_parse(o->csf ? o->csf : "castle", csf) != 0)
        return hl_fail(err, "--csf: unknown model '%s' (known: castle, stela)", o->csf);
    if (!(o->csf_scale > 0.0 && o->csf_scale <= 1000.0))
        return hl_fail(err, "--csf-scale: %g is outside (0, 1000]", o->csf_scale);
    return 0;
}

const char *frm_visibility_name(enum frm_visibility_criterion c)
{
    return (unsigned)c < 2 ? criterion_names[c] : "unknown";
}

static void visibility_fill(struct frm_visibility *v, double luminance_cdm2)
{
    acu_csf_table_fill_cycles(v->table, v->csf, luminance_cdm2, ACU_CSF_GABOR_CYCLES);
    v->adapting_luminance_cdm2 = luminance_cdm2;
}

int frm_visibility_open(struct frm_visibility *v, const struct frm_options *o, const struct hmd_profile *display,
                        const struct acu_limits *acuity, struct hl_error *err)
{
    memset(v, 0, sizeof *v);
    if (frm_visibility_options(o, &v->criterion, &v->csf, err) != 0)
        return -1;
    v->peak_luminance_cdm2 = display->peak_luminance_cdm2;
    v->adapting_luminance_cdm2 = NAN;
    if (v->criterion != FRM_VISIBILITY_CONTRAST)
        return 0;
    v->table = malloc(sizeof *v->table);
    if (!v->table)
        return hl_fail(err, "out of memory for the contrast sensitivity table (%zu bytes)", sizeof *v->table);
    visibility_fill(v, v->peak_luminance_cdm2 * FRM_ADAPT_FIRST_FRAME);
    acu_contrast_limits_init(&v->limits, v->table, acuity->xi_cpd, acuity->scale, o->csf_scale);
    v->limits.use_velocity = acuity->use_velocity;
    v->limits.use_eccentricity = acuity->use_eccentricity;
    return 0;
}

void frm_visibility_close(struct frm_visibility *v)
{
    free(v->table);
    memset(v, 0, sizeof *v);
}

void frm_visibility_adapt(struct frm_visibility *v, double mean_relative_luminance)
{
    if (!v->table || !(mean_relative_luminance >= 0.0 && mean_relative_luminance <= 1.0))
        return; /* a failed read keeps the last adaptation */
    /* A black frame adapts to the model's floor (acuity/csf.h clamps L at 0.02 cd/m²). */
    double l = fmax(v->peak_luminance_cdm2 * mean_relative_luminance, ACU_CSF_LUMINANCE_MIN_CDM2);
    double ratio = l / v->adapting_luminance_cdm2;
    if (ratio > FRM_ADAPT_REFILL_RATIO || ratio < 1.0 / FRM_ADAPT_REFILL_RATIO) {
        visibility_fill(v, l);
        ++v->refills;
    }
}
