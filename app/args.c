/* Strict argument parsing: a number must be all number, finite, and in range, or the message says
 * which option and why. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"

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
