/* acuity/csf.h: contrast sensitivity — the threshold side of DESIGN.md step 5 (a lost band is invisible
 * when its contrast times S is below 1). Part of the acuity/acuity.h umbrella. Two published models,
 * equations and parameters in PAPERS.md §6 (checked in tests/test_csf.c against the authors' code,
 * ../data/csf/castle.csv and stela.csv); docs/csf.md says how they differ from Reddy's H(v, E).
 * Allocates nothing.
 *   castle  castleCSF's achromatic mechanism (Ashraf et al. 2024), the default
 *   stela   stelaCSF (Mantiuk et al. 2022)
 * S is 1 / (threshold Michelson contrast) of a Gabor patch of area A deg² at spatial frequency ρ cpd,
 * temporal frequency ω Hz (ω = ρ·v for a pattern moving at v deg/s on the retina), adapting luminance
 * L cd/m² and eccentricity E deg (temporal visual field, vis_field 0).
 *
 * Hard cases (docs/HARD_CASES.md, "Contrast sensitivity"). The model functions take any non-NaN input
 * and return a finite S ≥ 0; NaN in gives NaN out — catch it at the boundary with acu_csf_check_inputs.
 *   ρ = 0 → S = 0 (the model's ·ρ factor); ρ ≫ 60 → finite, tiny; ρ = +∞ → 0; ρ < 0 → |ρ|.
 *   ω = 0 → still; ω huge or +∞ → both temporal responses → 0, S → 0 (never NaN); ω < 0 → |ω|.
 *   L is clamped to [0.02, 1e6] cd/m²: castleCSF's ω0 = 2.41482·log10 L + 4.7036 turns negative below
 *     0.0113 cd/m² (ω0^0.1898 would be NaN), the checked tables start at 1 cd/m², and S falls with L
 *     down there, so the floor over-states sensitivity (keeps detail). The cap only keeps ω0 and the
 *     transient gain finite (∞·0 at L = ∞).
 *   A ≤ 0 → S = 0 (no stimulus); A = +∞ → a full-field grating, finite.
 *   E is clamped to [0, 60]: the reference tables end at 60°, where castle already puts a contrast-1
 *     Gabor of 7 deg² below threshold (S ≤ 0.64 at 100 cd/m²); the exponential fall 10^(−(e_a + ρ·e_f)·E)
 *     extrapolated drops S tenfold every 23–30° more (at 1–0.5 cpd). Holding E at 60 over-states sensitivity in the far
 *     periphery, the side that keeps detail, rather than trusting an unchecked extrapolation. */
#ifndef HMDLOD_ACUITY_CSF_H
#define HMDLOD_ACUITY_CSF_H

#include "base/base.h"

enum acu_csf_model { ACU_CSF_CASTLE = 0, ACU_CSF_STELA = 1 };

/* "castle", "stela"; acu_csf_model_parse returns 0, or −1 for any other name (castle is the default
 * a caller should pick when none is given). */
const char *acu_csf_model_name(enum acu_csf_model model);
int acu_csf_model_parse(const char *name, enum acu_csf_model *out);

#define ACU_CSF_LUMINANCE_MIN_CDM2 0.02
#define ACU_CSF_LUMINANCE_MAX_CDM2 1e6
#define ACU_CSF_ECCENTRICITY_MAX_DEG 60.0

/* S(ρ, ω, L, A, E) = 1 / threshold Michelson contrast, PAPERS.md §6 exactly (sustained + transient
 * channels, eccentricity factor). Inputs outside the model's range are clamped as the header says;
 * finite ≥ 0 for any non-NaN input. About 10 pow/exp per call: per frame use the table below. */
double acu_csf_sensitivity(enum acu_csf_model model, double rho_cpd, double omega_hz, double luminance_cdm2,
                           double area_deg2, double eccentricity_deg);

/* Boundary check for user- or file-supplied values: NaN anywhere, negative ρ or ω, L not in (0, ∞),
 * A ≤ 0, E outside [0, 180] → −1 with the input named in err. +∞ ρ, ω and A are accepted (limits). */
int acu_csf_check_inputs(double rho_cpd, double omega_hz, double luminance_cdm2, double area_deg2,
                         double eccentricity_deg, struct hl_error *err);

/* ---- the per-frame table ---------------------------------------------------------------------
 * log10 S at E = 0 for one model, adapting luminance and area, on a grid of log2 ρ (2^−7 … 2^7 cpd,
 * 8 nodes an octave) × w = ω^0.1898 (0 … 511 Hz, 129 nodes uniform in w: the transient response is
 * exactly Gaussian in w, where a log(1 + ω) axis erred by up to 0.9 in log10 S near ω = 0; docs/csf.md).
 * The eccentricity factor is exactly log-linear in E (PAPERS.md §6), so it is applied in closed form:
 * the lookup is bilinear in (log ρ, w) plus −(e_a + ρ·e_f)·E, not interpolated in E. Error against
 * acu_csf_sensitivity (tests/test_csf.c: 900 000 random points, both models, L 0.02 … 1e6 cd/m²,
 * A 0.01 … 1e4 deg²): max |Δlog10 S| 0.0037 where S ≥ 1 (the kink of S_LP's plateau), 0.0064 anywhere;
 * asserted ≤ 0.01.
 * 116 KB: keep one per session (static or heap), not on a small stack. */
#define ACU_CSF_TABLE_RHO_LOG2_MIN (-7.0)
#define ACU_CSF_TABLE_RHO_NODES 113   /* 14 octaves · 8 + 1 */
#define ACU_CSF_TABLE_OMEGA_NODES 129     /* uniform in ω^0.1898 */
#define ACU_CSF_TABLE_OMEGA_W_MAX 3.2663  /* 511^0.1898: ω up to 511 Hz */
#define ACU_CSF_TABLE_NODES_PER_OCTAVE 8.0
struct acu_csf_table {
    enum acu_csf_model model;
    double luminance_cdm2, area_deg2; /* as given to the fill (clamped in the model, not here) */
    double area_cycles;               /* > 0: the area follows ρ, π·(cycles/(2ρ))² (fill_cycles); 0: area_deg2 */
    double ecc_a, ecc_f;              /* the model's e_a and e_f (per deg, per cpd·deg) */
    double log10_s[ACU_CSF_TABLE_OMEGA_NODES][ACU_CSF_TABLE_RHO_NODES]; /* at E = 0, floored at −300 */
};
/* Fills the table for one model, adapting luminance and stimulus area: the model is separable in ρ
 * and ω, so 113 spatial and 129 temporal evaluations and a log10 per node (about 0.1–0.2 ms here). */
void acu_csf_table_fill(struct acu_csf_table *t, enum acu_csf_model model, double luminance_cdm2,
                        double area_deg2);
/* The same with the stimulus area following the frequency: a disc `cycles` periods across,
 * A(ρ) = π·(cycles / (2ρ))² deg² (acu_csf_gabor_area_deg2). ACU_CSF_GABOR_CYCLES (1.5) is the
 * convention the selectors use: a lost LOD detail is a few cycles wide, not a fixed patch (docs/csf.md
 * "Stimulus area"). cycles > 0. */
#define ACU_CSF_GABOR_CYCLES 1.5
void acu_csf_table_fill_cycles(struct acu_csf_table *t, enum acu_csf_model model, double luminance_cdm2,
                               double cycles);
/* π·(cycles / (2ρ))², the area of a disc `cycles` periods of ρ cpd across; +∞ at ρ = 0. */
double acu_csf_gabor_area_deg2(double rho_cpd, double cycles);
/* S from the table, O(1), no allocation (about 50 ns, a quarter of the direct model). ρ and ω as the
 * model takes them (|·|); E clamped as the model does. Off the grid (ρ outside 2^−7 … 2^7 cpd, ω above
 * 511 Hz, NaN) it returns the direct model's value. */
double acu_csf_table_lookup(const struct acu_csf_table *t, double rho_cpd, double omega_hz, double eccentricity_deg);

/* ---- visibility -------------------------------------------------------------------------------
 * A band of contrast c is visible when c·S·k ≥ 1, i.e. c·S ≥ 1/k (k = --csf-scale, default 1; k > 1
 * keeps more). c is a band contrast (Peli 1990: band image over the local mean), so c > 1 is allowed
 * (a Michelson contrast cannot exceed 1, a band contrast can); c < 0 counts as |c|; c = 0 is never
 * visible. NaN anywhere → visible: a bad number never drops detail. */
int acu_csf_band_visible(double contrast, double sensitivity, double k_scale);
/* ---- a lost band on an object, per frame (acuity/contrast.c) ---------------------------------
 * What the contrast criterion needs beside the table (docs/visibility.md): the display's ξ, Reddy's
 * global factor s and the safety factor k. A band at ρ cpd is judged as at ρ/s — under the acuity
 * criterion s scales the limit (f > H·s ⇔ f/s > H), so under contrast it scales the frequency the
 * same way: s < 1 discards more. */
struct acu_contrast_limits {
    const struct acu_csf_table *csf; /* the frame's table: adapting luminance, 1.5-cycle area */
    double xi_cpd;                   /* above it nothing is displayed (Reddy eq. 4), > 0 */
    double scale;                    /* s in (0, 1]; 1 = plain */
    double k_scale;                  /* --csf-scale k > 0; 1 = threshold, > 1 keeps more */
    int use_velocity, use_eccentricity; /* 0 → still / at the gaze, as acu_limits */
};
void acu_contrast_limits_init(struct acu_contrast_limits *lim, const struct acu_csf_table *csf, double xi_cpd,
                              double scale, double k_scale);
/* The sensitivity a lost band at rho_cpd meets on an object moving at retinal velocity v and seen at
 * eccentricity E: 0 where ρ/s > ξ (not displayable, so never visible), else the table's
 * S(ρ/s, ρ/s·v, E) (ω = ρ·v: the pattern's temporal frequency on the retina). Feed it with the band's
 * contrast to acu_csf_band_visible(c, S, lim->k_scale). Inputs not NaN (checked at the boundary). */
double acu_contrast_band_sensitivity(const struct acu_contrast_limits *lim, double rho_cpd, double velocity_degps,
                                     double eccentricity_deg);

/* The same per object, band by band, for the selectors' hot loop: one object's octave bands
 * ρ_b = ρ_0·2^b (ρ_0 = 1/(D·s) cpd for an object D degrees across), prepared once so that each band
 * costs a table interpolation and no transcendental call (log2 ρ_b and ω_b^0.1898 follow from band 0
 * by an addition and a product). displayable_bands: bands 0 … n−1 have ρ_b ≤ ξ (the test of
 * acu_contrast_band_sensitivity); the others are never visible. */
struct acu_contrast_object {
    double rho0_cpd, log2_rho0, w0, eccentricity_deg, velocity_degps;
    int displayable_bands;
};
/* Prepares the object for bands 0 … band_count−1 (≤ 64). diameter_deg > 0; v and E as above. */
void acu_contrast_object_init(const struct acu_contrast_limits *lim, double diameter_deg, double velocity_degps,
                              double eccentricity_deg, int band_count, struct acu_contrast_object *obj);
/* log10 S of band b < obj->displayable_bands: log10 of acu_contrast_band_sensitivity(lim, 2^b / D, v, E)
 * to within the table's interpolation (the same table; off its ρ range the direct model). Above the
 * table's 511 Hz it returns the last row, an upper bound below 10^−6 (the lookup takes the model). */
double acu_contrast_object_log10_s(const struct acu_contrast_limits *lim, const struct acu_contrast_object *obj, int band);
/* acu_csf_band_visible(c, 10^log10_s, k) without the power where the exponents decide it: c·S·k ≥ 1
 * is read off c's binary exponent unless it lies within one octave of the threshold. log10_k = log10 k.
 * NaN c → visible; log10_s NaN or −∞ → not visible (as S = 0). */
int acu_csf_band_visible_log10(double contrast, double log10_s, double k_scale, double log10_k);

/* Boundary check for a contrast and k given by the user or a file: NaN, negative or infinite c,
 * and k not finite and > 0 → −1 with the input named in err. */
int acu_csf_check_contrast(double contrast, double k_scale, struct hl_error *err);

#endif
