/* Built-in display table, DEVICES.md §1a (geometry), §1b (distortion) and §1c (ξ checks).
 * Tangents are the LEFT eye's L (temporal) / R (nasal) / U / D magnitudes as the table gives them;
 * symmetric rows store tan(FOV/2). Refresh is the table's first value; IPD is 0.063 m unless the
 * table gives a lens separation. */
#include "hmd/hmd.h"

#include <ctype.h>
#include <math.h>
#include <stddef.h>

/* One row: a profile, plus a symmetric FOV in degrees for rows whose tangents are left zero; those
 * get tan(FOV/2) at first use (C has no constant-expression tan). */
struct builtin_row {
    struct hmd_profile p;
    double sym_h_deg, sym_v_deg; /* > 0: fill tangents as tan(fov/2) */
};

#define NO_K {0, 0, 0, 0}
#define NO_AB {1, 1, 1}
/* No headset publishes its wearer's neck: every row gets the Oculus SDK's average (hmd.h). */
#define NECK {HMD_NECK_TO_EYE_FORWARD_M, HMD_NECK_TO_EYE_UP_M}
/* DEVICES.md §1d gives a measured peak luminance only for the HTC Vive Pro (133.3 cd/m²), which is
 * not in this table; every row gets the documented default rather than a guess. */
#define LUM HMD_PEAK_LUMINANCE_DEFAULT_CDM2

static struct builtin_row g_rows[] = {
    {{"i-glasses", "Virtual i-O i-glasses HMD, Reddy 1998 s4 (video refresh, 60 Hz assumed)", 263, 230,
      0, 0, 0, 0, 60, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 30.0, 24.0},
    {{"desktop", "Reddy's desktop: 40x30 cm monitor at 40 cm, Reddy 1998 s4", 1280, 1024,
      0, 0, 0, 0, 60, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 53.1, 41.1},
    {{"dk1", "Oculus Rift DK1, pinhole screen-space FOV [OH] dummy defaults; OH distortion", 640, 800,
      1.052, 0.774, 1.141, 1.141, 60, 0.0635, {1.003, -1.005, 0.403, 0.599}, {0.985, 1.000, 1.015}, 0, NECK, LUM}, 0, 0},
    {{"dk2", "Oculus Rift DK2, [MO] rift_hmd.c angles; OH distortion", 960, 1080,
      1.0587, 1.0924, 1.3316, 1.3316, 75, 0.063, {0.247, -0.145, 0.103, 0.795}, {0.985, 1.000, 1.015}, 0, NECK, LUM}, 0, 0},
    {{"cv1", "Oculus Rift CV1, [HG] OculusRiftCV1_Native_R90 default FOV; OH distortion, lens sep 54 mm", 1080, 1200,
      0.9649, 0.7153, 0.8895, 1.1109, 90, 0.054, {0.098, 0.324, -0.241, 0.819}, {0.9952420, 1.0, 1.0008074}, 0, NECK, LUM},
     0, 0},
    {{"vive", "HTC Vive, [HG] Vive_Native_R90", 1080, 1200,
      1.3973, 1.2505, 1.4642, 1.4775, 90, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"index", "Valve Index, [HG] Index_Native_R144 (raw, canted view frame)", 1440, 1600,
      1.2791, 1.2587, 1.4140, 1.4086, 80, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"quest2", "Meta Quest 2, [HG] Quest2_Native_R72 (Link); pixels from spec", 1832, 1920,
      1.2799, 1.0000, 1.1106, 1.1918, 72, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"quest3", "Meta Quest 3, [HG] MetaQuest3_Native_R72; pixels from spec", 2064, 2208,
      1.3764, 0.8391, 0.9657, 1.4281, 72, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"psvr", "Sony PSVR, [MO] symmetric FOV (uncertain); MO distortion, OH lens sep 63.1 mm", 960, 1080,
      0.916, 0.916, 0.987, 0.987, 90, 0.0631, {0.75, -0.01, 0.75, 0}, {0.999, 1.008, 1.018}, 0, NECK, LUM}, 0, 0},
    {{"psvr2", "Sony PSVR2, [HG] PSVR2_Native_R90 (SteamVR); pixels from spec", 2000, 2040,
      1.8418, 0.9472, 1.3290, 1.3290, 90, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"varjo-aero", "Varjo Aero, [HG] VarjoAero_Native_R90; pixels from spec", 2880, 2720,
      1.5756, 0.7105, 0.8041, 1.1159, 90, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"varjo-focus", "Varjo XR-3 focus area, centred inset, spec sheet only (uncertain)", 1920, 1920,
      0, 0, 0, 0, 90, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 27.0, 27.0},
    {{"reverb-g2", "HP Reverb G2, [HG] ReverbG2_Native_R90; pixels from spec", 2160, 2160,
      1.1676, 0.9919, 1.0570, 1.0564, 90, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"pimax-crystal", "Pimax Crystal, [HG] PimaxCrystal_Native_R120; pixels from spec", 2880, 2880,
      1.2641, 0.8895, 1.2743, 1.2743, 72, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"hdk", "OSVR HDK 1.3/1.4, [MO] hdk_device.cpp (COP 0.529)", 960, 1080,
      0.943, 1.060, 1.126, 1.126, 60, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
    {{"hdk2", "OSVR HDK 2, [MO] 1080x1080 of the 1080x1200 panel used", 1080, 1080,
      1.036, 1.036, 1.036, 1.036, 90, 0.063, NO_K, NO_AB, 0, NECK, LUM}, 0, 0},
};

enum { ROW_COUNT = (int)(sizeof g_rows / sizeof g_rows[0]) };
static int g_ready;

/* Fills symmetric rows' tangents. Idempotent; the table is otherwise read-only. Not thread-safe on
 * the very first call (the program calls it from one thread before any workers start). */
static void ensure_ready(void)
{
    if (g_ready)
        return;
    for (int i = 0; i < ROW_COUNT; ++i) {
        struct builtin_row *r = &g_rows[i];
        if (r->sym_h_deg > 0)
            hmd_set_symmetric_fov_deg(&r->p, r->sym_h_deg, r->sym_v_deg);
    }
    g_ready = 1;
}

int hmd_builtin_count(void) { return ROW_COUNT; }

const struct hmd_profile *hmd_builtin_at(int index)
{
    if (index < 0 || index >= ROW_COUNT)
        return NULL;
    ensure_ready();
    return &g_rows[index].p;
}

const struct hmd_profile *hmd_builtin_find(const char *name)
{
    if (!name)
        return NULL;
    for (int i = 0; i < ROW_COUNT; ++i) {
        const char *a = g_rows[i].p.name, *b = name;
        while (*a && *b && tolower((unsigned char)*a) == tolower((unsigned char)*b))
            ++a, ++b;
        if (*a == 0 && *b == 0)
            return hmd_builtin_at(i);
    }
    return NULL;
}
