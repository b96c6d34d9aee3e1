/* Contrast sensitivity (acuity/csf.h): stelaCSF and castleCSF's achromatic mechanism, PAPERS.md §6,
 * and the per-frame table over (ρ, ω). Reproduces ../data/csf (castle.csv, stela.csv) (the authors' MATLAB code). */
#include "acuity/acuity.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* One channel (sustained or transient), PAPERS.md §6: S_max and f_max depend on L through 1-, 2-, 3- or
 * 5-parameter vectors; bw and a shape the truncated log-parabola S_LP; A0 and f0 the aperture term Ac. */
struct csf_channel {
    double s_max[5];
    int s_max_n;
    double f_max[3];
    int f_max_n;
    double bw, a, a0, f0;
};

struct csf_params {
    struct csf_channel sust, trans;
    double sigma_sust, sigma_trans;
    double omega0_slope, omega0_offset; /* ω0 = slope·log10 L + offset (stelaCSF: 0, 5 Hz) */
    double ecc_a, ecc_f;                /* 10^(−(e_a + ρ·e_f)·E), vis_field 0 */
};

/* PAPERS.md §6: stelaCSF (gfxdisp/stelaCSF defaults), vis_field 0. */
static const struct csf_params g_stela = {
    .sust = {{68.9501, 59.5023, 0.164274, 7.54866e-07, 7.77268e+09}, 5, {1.62144, 36.6565, 0.255823}, 3,
             0.000219263, 0.103686, 270.0, 0.65},
    .trans = {{0.500846, 57.3469}, 2, {0.0267489}, 1, 1.75147, 0.000273289, 270.0, 0.65},
    .sigma_sust = 5.79336,
    .sigma_trans = 0.12314,
    .omega0_slope = 0.0,
    .omega0_offset = 5.0,
    .ecc_a = 0.0296662,
    .ecc_f = 0.0190062,
};

/* PAPERS.md §6: castleCSF v0.2.0's achromatic mechanism, vis_field 0. */
static const struct csf_params g_castle = {
    .sust = {{56.4947, 7.54726, 0.144532, 5.58341e-07, 9.66862e+09}, 5, {1.78119, 91.5718, 0.256682}, 3,
             0.000213047, 0.100207, 157.103, 0.702338},
    .trans = {{0.193434, 2748.09}, 2, {0.000316696}, 1, 2.6761, 0.000241177, 3.81611, 3.01389},
    .sigma_sust = 10.5795,
    .sigma_trans = 0.0844836,
    .omega0_slope = 2.41482,
    .omega0_offset = 4.7036,
    .ecc_a = 0.0239853,
    .ecc_f = 0.0189038,
};

/* Temporal response exponents, the same in both models (PAPERS.md §6). */
#define CSF_BETA_SUST 1.3314
#define CSF_BETA_TRANS 0.1898
#define CSF_LOG10_FLOOR (-300.0)

static const char *const g_names[] = {"castle", "stela"};

const char *acu_csf_model_name(enum acu_csf_model model)
{
    return (unsigned)model < 2 ? g_names[model] : "unknown";
}

int acu_csf_model_parse(const char *name, enum acu_csf_model *out)
{
    for (int k = 0; name && k < 2; ++k) {
        if (strcmp(name, g_names[k]) == 0) {
            *out = (enum acu_csf_model)k;
            return 0;
        }
    }
    return -1;
}

static const struct csf_params *csf_params_of(enum acu_csf_model model)
{
    return model == ACU_CSF_STELA ? &g_stela : &g_castle;
}

/* PAPERS.md §6 luminance dependence: 1 value p1; 2: p2·L^p1; 3: p1·(1 + p2/L)^−p3;
 * 5: p1·(1 + p2/L)^−p3·(1 − (1 + p4/L)^−p5). The powers of (1 + x) go through log1p and the last
 * factor through expm1: p4/L is ~1e-9, where 1 + p4/L rounded loses half its digits. */
static double csf_lum_dep(const double *p, int n, double lum)
{
    if (n == 1)
        return p[0];
    if (n == 2)
        return p[1] * pow(lum, p[0]);
    double v = p[0] * exp(-p[2] * log1p(p[1] / lum));
    if (n == 5)
        v *= -expm1(-p[4] * log1p(p[3] / lum));
    return v;
}

/* What depends only on the model, L and A: computed once per call, or once per table. */
struct csf_prepared {
    const struct csf_params *par;
    double s_max[2], f_max[2]; /* sustained, transient */
    double omega0_pow;         /* ω0^0.1898 */
    double area_deg2;
};

static void csf_prepare(struct csf_prepared *pr, enum acu_csf_model model, double lum, double area)
{
    const struct csf_params *par = csf_params_of(model);
    lum = lum < ACU_CSF_LUMINANCE_MIN_CDM2 ? ACU_CSF_LUMINANCE_MIN_CDM2
          : lum > ACU_CSF_LUMINANCE_MAX_CDM2 ? ACU_CSF_LUMINANCE_MAX_CDM2
                                             : lum; /* NaN stays NaN */
    pr->par = par;
    pr->s_max[0] = csf_lum_dep(par->sust.s_max, par->sust.s_max_n, lum);
    pr->f_max[0] = csf_lum_dep(par->sust.f_max, par->sust.f_max_n, lum);
    pr->s_max[1] = csf_lum_dep(par->trans.s_max, par->trans.s_max_n, lum);
    pr->f_max[1] = csf_lum_dep(par->trans.f_max, par->trans.f_max_n, lum);
    /* castleCSF: ω0 = 2.41482·log10 L + 4.7036, > 0.6 Hz at the luminance floor. */
    pr->omega0_pow = pow(par->omega0_slope * log10(lum) + par->omega0_offset, CSF_BETA_TRANS);
    pr->area_deg2 = area <= 0.0 ? 0.0 : area; /* A ≤ 0: no stimulus, S = 0; NaN stays NaN */
}

/* PAPERS.md §6 per channel: S_c = S_max·S_LP·sqrt(Ac / (1 + Ac/A))·ρ. ρ finite and ≥ 0. */
static double csf_channel_s(const struct csf_channel *c, double s_max, double f_max, double rho, double area)
{
    double x = log10(rho / f_max); /* −∞ at ρ = 0: S_LP → 0, then the plateau below */
    double s_lp = pow(10.0, -x * x / exp2(c->bw));
    if (rho < f_max && s_lp < 1.0 - c->a)
        s_lp = 1.0 - c->a; /* the low-frequency plateau */
    if (area == 0.0)
        return 0.0; /* no stimulus (and Ac/A would be 0/0 where Ac underflows) */
    double q = rho / c->f0;
    double ac = c->a0 / (1.0 + q * q); /* 0 once q² overflows */
    return s_max * s_lp * sqrt(ac / (1.0 + ac / area)) * rho;
}

/* The model is separable (PAPERS.md §6): S = (R_sust(ω)·S_sust(ρ) + R_trans(ω)·S_trans(ρ)) · ecc(ρ, E).
 * The spatial part, ρ finite and ≥ 0: */
static void csf_spatial_area(const struct csf_prepared *pr, double rho, double area, double *s_sust,
                             double *s_trans)
{
    *s_sust = csf_channel_s(&pr->par->sust, pr->s_max[0], pr->f_max[0], rho, area);
    *s_trans = csf_channel_s(&pr->par->trans, pr->s_max[1], pr->f_max[1], rho, area);
}

static void csf_spatial(const struct csf_prepared *pr, double rho, double *s_sust, double *s_trans)
{
    csf_spatial_area(pr, rho, pr->area_deg2, s_sust, s_trans);
}

double acu_csf_gabor_area_deg2(double rho_cpd, double cycles)
{
    double radius_deg = 0.5 * cycles / fabs(rho_cpd); /* +∞ at ρ = 0 */
    return HL_PI * radius_deg * radius_deg;
}

/* The temporal responses, ω ≥ 0; at ω = +∞ both exponents are −∞ and the responses exactly 0. */
static void csf_temporal(const struct csf_prepared *pr, double omega, double *r_sust, double *r_trans)
{
    *r_sust = exp(-pow(omega, CSF_BETA_SUST) / pr->par->sigma_sust);
    double d = pow(omega, CSF_BETA_TRANS) - pr->omega0_pow;
    *r_trans = exp(-d * d / pr->par->sigma_trans);
}

static double csf_clamp_eccentricity(double ecc)
{
    return ecc < 0.0 ? 0.0 : ecc > ACU_CSF_ECCENTRICITY_MAX_DEG ? ACU_CSF_ECCENTRICITY_MAX_DEG : ecc;
}

static double csf_eval(const struct csf_prepared *pr, double rho, double omega, double ecc)
{
    rho = fabs(rho);
    omega = fabs(omega);
    if (rho == INFINITY)
        return 0.0; /* S_LP and Ac vanish faster than ρ grows; ∞·0 avoided */
    double s_sust, s_trans, r_sust, r_trans;
    csf_spatial(pr, rho, &s_sust, &s_trans);
    csf_temporal(pr, omega, &r_sust, &r_trans);
    double s = r_sust * s_sust + r_trans * s_trans;
    return s * pow(10.0, -(pr->par->ecc_a + rho * pr->par->ecc_f) * csf_clamp_eccentricity(ecc));
}

double acu_csf_sensitivity(enum acu_csf_model model, double rho_cpd, double omega_hz, double luminance_cdm2,
                           double area_deg2, double eccentricity_deg)
{
    struct csf_prepared pr;
    csf_prepare(&pr, model, luminance_cdm2, area_deg2);
    return csf_eval(&pr, rho_cpd, omega_hz, eccentricity_deg);
}

int acu_csf_check_inputs(double rho_cpd, double omega_hz, double luminance_cdm2, double area_deg2,
                         double eccentricity_deg, struct hl_error *err)
{
    if (isnan(rho_cpd))
        return hl_fail(err, "spatial frequency: not a number");
    if (rho_cpd < 0.0)
        return hl_fail(err, "spatial frequency: %g cpd is negative", rho_cpd);
    if (isnan(omega_hz))
        return hl_fail(err, "temporal frequency: not a number");
    if (omega_hz < 0.0)
        return hl_fail(err, "temporal frequency: %g Hz is negative", omega_hz);
    if (isnan(luminance_cdm2))
        return hl_fail(err, "luminance: not a number");
    if (!(luminance_cdm2 > 0.0 && isfinite(luminance_cdm2)))
        return hl_fail(err, "luminance: %g cd/m2 is not a positive finite number", luminance_cdm2);
    if (isnan(area_deg2))
        return hl_fail(err, "area: not a number");
    if (!(area_deg2 > 0.0))
        return hl_fail(err, "area: %g deg2 is not positive", area_deg2);
    if (isnan(eccentricity_deg))
        return hl_fail(err, "eccentricity: not a number");
    if (eccentricity_deg < 0.0 || eccentricity_deg > 180.0)
        return hl_fail(err, "eccentricity: %g deg is outside [0, 180]", eccentricity_deg);
    return 0;
}

/* The ω axis is w = ω^0.1898, uniform from 0 to 511^0.1898 (PAPERS.md §6: ln R_trans = −(w − w0)²/σ is
 * exactly quadratic in w and ln R_sust = −w^7.01/σ smooth at 0). On log(1 + ω) the transient term's
 * infinite slope at ω = 0 cost up to 0.02–0.9 in log10 S in the first cell (docs/csf.md). */
static const double csf_omega_per_w = (ACU_CSF_TABLE_OMEGA_NODES - 1) / ACU_CSF_TABLE_OMEGA_W_MAX;

static double csf_omega_axis(double omega)
{
    return pow(omega, CSF_BETA_TRANS) * csf_omega_per_w;
}

static double csf_omega_node_hz(int j)
{
    return pow(j * (ACU_CSF_TABLE_OMEGA_W_MAX / (ACU_CSF_TABLE_OMEGA_NODES - 1)), 1.0 / CSF_BETA_TRANS);
}

/* Shared by both fills: area_cycles > 0 makes the area follow ρ node by node. */
static void csf_table_fill_any(struct acu_csf_table *t, enum acu_csf_model model, double luminance_cdm2,
                               double area_deg2, double area_cycles)
{
    struct csf_prepared pr;
    csf_prepare(&pr, model, luminance_cdm2, area_deg2);
    t->model = model;
    t->luminance_cdm2 = luminance_cdm2;
    t->area_deg2 = area_deg2;
    t->area_cycles = area_cycles;
    t->ecc_a = pr.par->ecc_a;
    t->ecc_f = pr.par->ecc_f;
    /* Separable: one spatial evaluation per ρ node and one temporal per ω node, then a product per cell. */
    double s_sust[ACU_CSF_TABLE_RHO_NODES], s_trans[ACU_CSF_TABLE_RHO_NODES];
    for (int i = 0; i < ACU_CSF_TABLE_RHO_NODES; ++i) {
        double rho = exp2(ACU_CSF_TABLE_RHO_LOG2_MIN + i / ACU_CSF_TABLE_NODES_PER_OCTAVE);
        double area = area_cycles > 0.0 ? acu_csf_gabor_area_deg2(rho, area_cycles) : pr.area_deg2;
        csf_spatial_area(&pr, rho, area, &s_sust[i], &s_trans[i]);
    }
    for (int j = 0; j < ACU_CSF_TABLE_OMEGA_NODES; ++j) {
        double r_sust, r_trans;
        csf_temporal(&pr, csf_omega_node_hz(j), &r_sust, &r_trans);
        for (int i = 0; i < ACU_CSF_TABLE_RHO_NODES; ++i) {
            double l = log10(r_sust * s_sust[i] + r_trans * s_trans[i]); /* −∞ if S underflowed */
            t->log10_s[j][i] = l > CSF_LOG10_FLOOR ? l : CSF_LOG10_FLOOR;
        }
    }
}

void acu_csf_table_fill(struct acu_csf_table *t, enum acu_csf_model model, double luminance_cdm2,
                        double area_deg2)
{
    csf_table_fill_any(t, model, luminance_cdm2, area_deg2, 0.0);
}

void acu_csf_table_fill_cycles(struct acu_csf_table *t, enum acu_csf_model model, double luminance_cdm2,
                               double cycles)
{
    csf_table_fill_any(t, model, luminance_cdm2, 0.0, cycles);
}

/* log10 S at E = 0, bilinear in the table's (log ρ, ω^0.1898) nodes; x and y in node units, inside
 * [0, nodes − 1] (the callers check). */
static double csf_table_interp(const struct acu_csf_table *t, double x, double y)
{
    int i = (int)x, j = (int)y;
    i = i < ACU_CSF_TABLE_RHO_NODES - 1 ? i : ACU_CSF_TABLE_RHO_NODES - 2;
    j = j < ACU_CSF_TABLE_OMEGA_NODES - 1 ? j : ACU_CSF_TABLE_OMEGA_NODES - 2;
    double fx = x - i, fy = y - j;
    const double *r0 = t->log10_s[j], *r1 = t->log10_s[j + 1];
    return (1.0 - fy) * ((1.0 - fx) * r0[i] + fx * r0[i + 1]) + fy * ((1.0 - fx) * r1[i] + fx * r1[i + 1]);
}

double acu_csf_table_lookup(const struct acu_csf_table *t, double rho_cpd, double omega_hz, double eccentricity_deg)
{
    double rho = fabs(rho_cpd), omega = fabs(omega_hz);
    double x = (log2(rho) - ACU_CSF_TABLE_RHO_LOG2_MIN) * ACU_CSF_TABLE_NODES_PER_OCTAVE;
    double y = csf_omega_axis(omega);
    if (!(x >= 0.0 && x <= ACU_CSF_TABLE_RHO_NODES - 1 && y <= ACU_CSF_TABLE_OMEGA_NODES - 1)) {
        double area = t->area_cycles > 0.0 ? acu_csf_gabor_area_deg2(rho, t->area_cycles) : t->area_deg2;
        return acu_csf_sensitivity(t->model, rho, omega, t->luminance_cdm2, area, eccentricity_deg);
    }
    /* PAPERS.md §6 eccentricity factor, exact: log10 S falls by (e_a + ρ·e_f) per degree. */
    return pow(10.0, csf_table_interp(t, x, y) - (t->ecc_a + rho * t->ecc_f) * csf_clamp_eccentricity(eccentricity_deg));
}

/* ---- the selectors' per-object octave bands (csf.h "per object, band by band") ---------------- */

/* 2^(0.1898·b): band b's ω^0.1898 over band 0's (tests/test_csf.c checks it against exp2). */
static const double csf_octave_w_step[16] = {
    1.0, 1.1406055833989166, 1.300981096880783, 1.4839063029986677, 1.6925518144411247, 1.930534049743514,
    2.2019779160791737, 2.5115883056010166, 2.864731644567944, 3.267528908733757, 3.7269617172190923,
    4.250993343774111, 4.848706742900381, 5.530461983216149, 6.308075816831785, 7.195026497182015};

void acu_contrast_object_init(const struct acu_contrast_limits *lim, double diameter_deg, double velocity_degps,
                              double eccentricity_deg, int band_count, struct acu_contrast_object *obj)
{
    double v = lim->use_velocity ? fabs(velocity_degps) : 0.0;
    obj->rho0_cpd = 1.0 / diameter_deg / lim->scale;
    obj->log2_rho0 = log2(obj->rho0_cpd);
    obj->velocity_degps = v;
    /* (ρ0·v)^β as 2^(β·(log2 ρ0 + log2 v)): log2 ρ0 is already here, and log2 + exp2 cost less than pow. */
    obj->w0 = v > 0.0 ? exp2(CSF_BETA_TRANS * (obj->log2_rho0 + log2(v))) * csf_omega_per_w : 0.0;
    obj->eccentricity_deg = lim->use_eccentricity ? eccentricity_deg : 0.0;
    /* The same test as acu_contrast_band_sensitivity, band by band: ρ grows with b, so the
     * displayable bands are a prefix. Doubling is exact, so ρ_b here is 2^b/D/s to the bit. */
    int n = 0;
    for (double rho = obj->rho0_cpd; n < band_count && n < 64 && !(rho > lim->xi_cpd); rho *= 2.0)
        ++n;
    obj->displayable_bands = n;
}

double acu_contrast_object_log10_s(const struct acu_contrast_limits *lim, const struct acu_contrast_object *obj, int band)
{
    const struct acu_csf_table *t = lim->csf;
    double rho = obj->rho0_cpd * (double)(1ull << (band & 63)); /* exact, as ldexp, without the call */
    /* log2 ρ_b = log2 ρ_0 + b and w_b = (ρ_b·v)^β = w_0·2^(β·b): no transcendental per band. */
    double x = (obj->log2_rho0 + band - ACU_CSF_TABLE_RHO_LOG2_MIN) * ACU_CSF_TABLE_NODES_PER_OCTAVE;
    double step = band < 16 ? csf_octave_w_step[band] : exp2(CSF_BETA_TRANS * band);
    double y = obj->w0 > 0.0 ? obj->w0 * step : 0.0;
    if (!(x >= 0.0 && x <= ACU_CSF_TABLE_RHO_NODES - 1))
        return log10(acu_csf_table_lookup(t, rho, rho * obj->velocity_degps, obj->eccentricity_deg)); /* the model */
    /* Beyond 511 Hz S only falls (both temporal responses decrease past ω0, which is under 20 Hz for
     * any luminance up to 10^6 cd/m²), so the last row bounds it from above — and is itself below
     * 10^−6 (tests/test_csf.c): no band there is visible unless its contrast exceeds 10^6/k. Fast
     * objects under the head-locked gaze land here often; the direct model would cost 20× more. */
    y = y < ACU_CSF_TABLE_OMEGA_NODES - 1 ? y : ACU_CSF_TABLE_OMEGA_NODES - 1;
    return csf_table_interp(t, x, y) - (t->ecc_a + rho * t->ecc_f) * csf_clamp_eccentricity(obj->eccentricity_deg);
}

int acu_csf_band_visible_log10(double contrast, double log10_s, double k_scale, double log10_k)
{
    double c = fabs(contrast);
    if (isnan(c))
        return 1;
    if (!(log10_s > -INFINITY) || c == 0.0)
        return 0;
    /* Visible ⇔ log2 c ≥ t, t = −(log10 S + log10 k)·log2 10. With c = m·2^e, m ∈ [1, 2):
     * m − 1 ≤ log2 m ≤ m − 1 + 0.0861 (log2 is concave and meets m − 1 at both ends; the gap peaks at
     * m = 1/ln 2), so only c within 0.09 octave of the threshold needs the power. */
    if (c >= DBL_MIN && c <= DBL_MAX) {
        double t = -(log10_s + log10_k) * 3.321928094887362;
        int e;
        double m = 2.0 * frexp(c, &e); /* c = m·2^(e−1) */
        double lo = (double)(e - 1) + (m - 1.0);
        if (lo >= t + 1e-9)
            return 1;
        if (lo + 0.0861 <= t - 1e-9)
            return 0;
    }
    return acu_csf_band_visible(c, pow(10.0, log10_s), k_scale);
}

int acu_csf_band_visible(double contrast, double sensitivity, double k_scale)
{
    /* Written so that NaN compares false and counts as visible. */
    return !(fabs(contrast) * sensitivity * k_scale < 1.0);
}

int acu_csf_check_contrast(double contrast, double k_scale, struct hl_error *err)
{
    if (isnan(contrast))
        return hl_fail(err, "contrast: not a number");
    if (contrast < 0.0 || !isfinite(contrast))
        return hl_fail(err, "contrast: %g is not a finite number >= 0", contrast);
    if (isnan(k_scale))
        return hl_fail(err, "csf scale: not a number");
    if (!(k_scale > 0.0 && isfinite(k_scale)))
        return hl_fail(err, "csf scale: %g is not a positive finite number", k_scale);
    return 0;
}
