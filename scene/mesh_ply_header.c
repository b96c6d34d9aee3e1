/* scene/mesh_ply_header.c: PLY and OFF headers checked before OpenMesh reads them. OpenMesh 9.0's PLY
 * reader reads the header token by token until the token "end_header" and checks only the stream's
 * badbit: at the end of the file, or after a count that is not a number (failbit), it loops for
 * ever, logging each turn (found by fuzz_mesh_import: a run-on end_header, a version that is not a
 * number). So the header must be what the PLY format
 * says, line by line: "ply", one "format" line, then comment / obj_info / element NAME COUNT /
 * property TYPE NAME / property list TYPE TYPE NAME lines, and a line "end_header" — on which
 * OpenMesh's loop ends. Anything else is refused with the line and the reason. */
#include "scene/lodgen_internal.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { PLY_HEADER_MAX_LINES = 4096, PLY_LINE_MAX = 1024, PLY_MAX_WORDS = 6 };

static int ply_is_type(const char *w)
{
    static const char *const types[] = {"char",  "uchar", "short",  "ushort", "int",    "uint",
                                        "float", "double", "int8",  "uint8",  "int16",  "uint16",
                                        "int32", "uint32", "float32", "float64"};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (!strcmp(w, types[i]))
            return 1;
    return 0;
}

/* Splits line at blanks into at most PLY_MAX_WORDS + 1 words (the extra one only counts). */
static int ply_words(char *line, char **w)
{
    int n = 0;
    for (char *p = strtok(line, " \t\r"); p; p = strtok(NULL, " \t\r"))
        if (n <= PLY_MAX_WORDS)
            w[n++] = p;
    return n;
}

static int ply_is_count(const char *s)
{
    if (!*s)
        return 0;
    for (const char *p = s; *p; ++p)
        if (!isdigit((unsigned char)*p))
            return 0;
    return strlen(s) <= 10 && strtoull(s, NULL, 10) <= 2147483647ULL; /* OpenMesh reads an int */
}

/* One header line without its newline into buf: 0, or −1 at the end of the file before a newline,
 * −2 for a line longer than the buffer, −3 for a NUL byte (OpenMesh would read past it). */
static int ply_read_line(FILE *f, char *buf, size_t size)
{
    size_t n = 0;
    for (;;) {
        int c = getc(f);
        if (c == EOF)
            return -1;
        if (c == '\n')
            break;
        if (c == '\0')
            return -3;
        if (n + 1 >= size)
            return -2;
        buf[n++] = (char)c;
    }
    buf[n] = '\0';
    return 0;
}

/* OpenMesh reads the version as a number: anything else sets failbit, and its loop never ends. */
static int ply_is_version(const char *s)
{
    int digits = 0, dots = 0;
    for (const char *p = s; *p; ++p) {
        if (isdigit((unsigned char)*p))
            ++digits;
        else if (*p == '.' && dots == 0 && digits > 0)
            ++dots;
        else
            return 0;
    }
    return digits > 0 && strlen(s) <= 16 && s[strlen(s) - 1] != '.';
}

int scn_ply_header_check(const char *path, struct hl_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return hl_fail(err, "%s: cannot open", path);
    char line[PLY_LINE_MAX + 1];
    int rc = -1;
    for (int n = 1; n <= PLY_HEADER_MAX_LINES; ++n) {
        int got = ply_read_line(f, line, sizeof line);
        if (got == -1) {
            hl_fail(err, "%s: line %d: PLY header ends without an end_header line", path, n);
            goto done;
        }
        if (got == -2) {
            hl_fail(err, "%s: line %d: PLY header line longer than %d bytes", path, n, PLY_LINE_MAX);
            goto done;
        }
        if (got == -3) {
            hl_fail(err, "%s: line %d: NUL byte in the PLY header", path, n);
            goto done;
        }
        char *w[PLY_MAX_WORDS + 1];
        int k = ply_words(line, w);
        const char *why = NULL;
        if (n == 1)
            why = k == 1 && !strcmp(w[0], "ply") ? NULL : "not a PLY file (the first line must be \"ply\")";
        else if (k == 0)
            why = "empty line in the PLY header";
        else if (!strcmp(w[0], "end_header")) {
            if (k == 1)
                rc = 0;
            else
                why = "end_header followed by more words";
            if (!why)
                goto done;
        } else if (!strcmp(w[0], "comment") || !strcmp(w[0], "obj_info"))
            why = NULL;
        else if (!strcmp(w[0], "format"))
            why = k == 3 && (!strcmp(w[1], "ascii") || !strcmp(w[1], "binary_little_endian") ||
                             !strcmp(w[1], "binary_big_endian")) && ply_is_version(w[2])
                      ? NULL
                      : "format must be \"format ascii|binary_little_endian|binary_big_endian VERSION\" (VERSION "
                        "a number such as 1.0)";
        else if (!strcmp(w[0], "element"))
            why = k == 3 && ply_is_count(w[2]) ? NULL : "element must be \"element NAME COUNT\" (COUNT a whole number)";
        else if (!strcmp(w[0], "property"))
            why = (k == 3 && ply_is_type(w[1])) || (k == 5 && !strcmp(w[1], "list") && ply_is_type(w[2]) &&
                                                    ply_is_type(w[3]))
                      ? NULL
                      : "property must be \"property TYPE NAME\" or \"property list TYPE TYPE NAME\"";
        else
            why = "unknown PLY header keyword";
        if (why) {
            hl_fail(err, "%s: line %d: %s", path, n, why);
            goto done;
        }
    }
    hl_fail(err, "%s: PLY header longer than %d lines", path, PLY_HEADER_MAX_LINES);
done:
    fclose(f);
    return rc;
}

/* OFF: OpenMesh 9.0's OFF reader takes the first line's first letters as the keyword and reserves
 * the vertex and face counts that follow before reading a single vertex, so a 100-byte file whose
 * first line is "OFF" run into other bytes made it reserve 8 GiB (found by fuzz_mesh_import). The
 * first line must be a keyword ([ST][C][N][4]OFF, optionally " BINARY"; nOFF, whose dimension line
 * changes the layout, is not supported) or that keyword followed by the counts, and the counts must
 * fit the file: at least 6 bytes a vertex and 8 a face in text ("0 0 0\n", "3 0 1 2\n"), 12 and 16
 * in binary. */
static int off_keyword(const char *w)
{
    const char *p = w;
    if (!strncmp(p, "ST", 2))
        p += 2;
    if (*p == 'C')
        ++p;
    if (*p == 'N')
        ++p;
    if (*p == '4')
        ++p;
    return !strcmp(p, "OFF");
}

int scn_off_header_check(const char *path, uint64_t file_size, struct hl_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return hl_fail(err, "%s: cannot open", path);
    char line[PLY_LINE_MAX + 1];
    char *w[PLY_MAX_WORDS + 1];
    int rc = -1, binary = 0, n = 1, k;
    int got = ply_read_line(f, line, sizeof line);
    if (got != 0) {
        hl_fail(err, "%s: line 1: %s", path,
                got == -3 ? "NUL byte in the OFF header" : "no OFF keyword line (OFF, COFF, NOFF, STOFF …)");
        goto done;
    }
    k = ply_words(line, w);
    if (k < 1 || !off_keyword(w[0])) {
        hl_fail(err, "%s: line 1: not an OFF file (the first line must start with OFF, COFF, NOFF, STOFF …)", path);
        goto done;
    }
    int first = 1;
    if (k >= 2 && !strcmp(w[1], "BINARY"))
        binary = 1, first = 2;
    if (k == first) { /* the counts on the next line that is not blank or a comment */
        for (;;) {
            ++n;
            got = ply_read_line(f, line, sizeof line);
            if (got != 0) {
                hl_fail(err, "%s: line %d: %s", path, n,
                        got == -1 ? "OFF header ends without the vertex and face counts" : "bad OFF counts line");
                goto done;
            }
            if (binary) /* binary OFF: the counts are binary too; the size check below is all we can do */
                break;
            k = ply_words(line, w);
            first = 0;
            if (k > 0 && w[0][0] != '#')
                break;
        }
    }
    if (!binary) {
        if (k - first != 3 || !ply_is_count(w[first]) || !ply_is_count(w[first + 1]) || !ply_is_count(w[first + 2])) {
            hl_fail(err, "%s: line %d: the OFF counts must be three whole numbers (vertices faces edges)", path, n);
            goto done;
        }
        uint64_t nv = strtoull(w[first], NULL, 10), nf = strtoull(w[first + 1], NULL, 10);
        if (nv * 6 + nf * 8 > file_size) {
            hl_fail(err, "%s: line %d: %llu vertices and %llu faces cannot fit in a file of %llu bytes", path, n,
                    (unsigned long long)nv, (unsigned long long)nf, (unsigned long long)file_size);
            goto done;
        }
    }
    rc = 0;
done:
    fclose(f);
    return rc;
}
