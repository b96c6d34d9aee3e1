/* Strict argument parsing: a number must be all number, finite, and in range, or the message says
 * which option and why. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "frame/frame.h"

int app_parse_double(const char *option, const char *text, double *out)
{
    if (!text) {
        fprintf(stderr, "hmdlod: %s needs a value\n", option);
        return -1;
    }
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || errno == ERANGE || isnan(v)) {
        fprintf(stderr, "hmdlod: %s: '%s' is not a number\n", option, text);
        return -1;
    }
    *out = v;
    return 0;
}

int app_parse_long(const char *option, const char *text, long min, long max, long *out)
{
    if (!text) {
        fprintf(stderr, "hmdlod: %s needs a value\n", option);
        return -1;
    }
    char *end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno == ERANGE) {
        fprintf(stderr, "hmdlod: %s: '%s' is not a whole number\n", option, text);
        return -1;
    }
    if (v < min || v > max) {
        fprintf(stderr, "hmdlod: %s: %ld is outside [%ld, %ld]\n", option, v, min, max);
        return -1;
    }
    *out = v;
    return 0;
}

int app_wants_help(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h"))
            return 1;
    return 0;
}

const char app_layer_usage[] =
    "  --foveation MODE   foveated layers (docs/foveation.md): off (default), fixed (a full-resolution\n"
    "                     inset on the lens centre) or gaze (on the gaze model's gaze: the tracked gaze\n"
    "                     under --gaze tracked); the periphery at a scale chosen per frame with the LODs;\n"
    "                     or adaptive (no inset: the whole eye at the scale Valve's adaptive-quality\n"
    "                     controller sets from the measured draw time, for comparison)\n"
    "  --periphery-scale S  fix the periphery's scale: 1, 0.75, 0.5, 0.35 or 0.25 (default: chosen)\n"
    "  --inset-deg R      fix the inset's radius in [0, 60] degrees (default: the resolution ceiling's,\n"
    "                     at most 5 from the gaze; 0 = no inset, the whole eye at the periphery's scale)\n"
    "  --blend-deg B      the blend band beyond the inset, (0, 20] degrees (default 5)\n";

int app_parse_layer_option(const char *opt, const char *val, struct frm_options *o, int *bad)
{
    double *target = !strcmp(opt, "--periphery-scale") ? &o->periphery_scale
                     : !strcmp(opt, "--inset-deg")     ? &o->inset_deg
                     : !strcmp(opt, "--blend-deg")     ? &o->blend_deg
                                                       : NULL;
    if (!strcmp(opt, "--foveation")) {
        o->foveation = val;
        return 1;
    }
    if (!target)
        return 0;
    if (app_parse_double(opt, val, target) != 0)
        *bad = 1;
    else if (target == &o->blend_deg && !(*target > 0.0)) {
        fprintf(stderr, "hmdlod: --blend-deg: %s is not a positive width in degrees\n", val);
        *bad = 1;
    } else if (target == &o->inset_deg && !(*target >= 0.0)) {
        fprintf(stderr, "hmdlod: --inset-deg: %s is outside [0, 60]\n", val);
        *bad = 1;
    }
    return 1;
}
