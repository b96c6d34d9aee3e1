/* Text helpers shared by the two row readers (trace_parse.c, trace_edvam.c): trimming, quoting a
 * field for a message, and reading one field as a finite number with a message naming its column. */
#include "replay/trace_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FIELD_MAX_BYTES 64 /* a number longer than this is not one a tracker writes */

static int is_blank(char c) { return c == ' ' || c == '\t'; }

void trace_trim(const char **s, size_t *n)
{
    while (*n > 0 && (is_blank(**s) || **s == '\r'))
        ++*s, --*n;
    while (*n > 0 && (is_blank((*s)[*n - 1]) || (*s)[*n - 1] == '\r'))
        --*n;
}

size_t trace_count_content_lines(const char *text, size_t length)
{
    size_t rows = 0, pos = 0;
    while (pos < length) {
        const char *line = text + pos;
        const char *nl = memchr(line, '\n', length - pos);
        size_t n = nl ? (size_t)(nl - line) : length - pos;
        pos += n + (nl ? 1 : 0);
        const char *s = line;
        trace_trim(&s, &n);
        rows += n > 0 && s[0] != '#';
    }
    return rows > 0 ? rows : 1;
}

void trace_quote_field(const char *s, size_t n, char *buf, size_t size)
{
    size_t k = 0;
    for (size_t i = 0; i < n && k + 4 < size; ++i) {
        unsigned char c = (unsigned char)s[i];
        buf[k++] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    if (n > 0 && k + 4 >= size && k < n) {
        buf[k++] = '.', buf[k++] = '.', buf[k++] = '.';
    }
    buf[k] = '\0';
}

int trace_read_number(const char *name, size_t line_no, const char *column, const char *s, size_t n, double *x,
                      struct hl_error *err)
{
    trace_trim(&s, &n);
    char shown[48];
    trace_quote_field(s, n, shown, sizeof shown);
    if (n == 0)
        return hl_fail(err, "%s:%zu: column %s: empty field", name, line_no, column);
    if (n > FIELD_MAX_BYTES)
        return hl_fail(err, "%s:%zu: column %s: not a number (%zu bytes): \"%s\"", name, line_no, column, n, shown);
    char buf[FIELD_MAX_BYTES + 1];
    memcpy(buf, s, n); /* bounded copy: strtod needs a NUL the input may not have */
    buf[n] = '\0';
    char *end = NULL;
    double v = strtod(buf, &end);
    if (end != buf + n || end == buf)
        return hl_fail(err, "%s:%zu: column %s: not a number: \"%s\"", name, line_no, column, shown);
    if (!isfinite(v))
        return hl_fail(err, "%s:%zu: column %s: not finite: \"%s\"", name, line_no, column, shown);
    *x = v;
    return 0;
}
