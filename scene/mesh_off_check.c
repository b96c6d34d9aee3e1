/* scene/mesh_off_check.c: an OFF file checked before OpenMesh 9.0 reads it. Its OFF reader trusts
 * the file twice over (both found by fuzz_mesh_import):
 *  - it takes the first line's first letters as the keyword and reserves the vertex and face counts
 *    before reading a single vertex: a 100-byte file whose first line ran "OFF" into other bytes
 *    made it reserve 8 GiB. So the counts must fit the file (at least 6 bytes a vertex, "0 0 0\n",
 *    and 8 a face, "3 0 1 2\n").
 *  - it reads each face's vertex count as an unsigned number and then pushes that many vertex
 *    handles, whether or not the stream still reads: a face "-1" (or a stray token read as one)
 *    asked for 4 294 967 295 of them, 16 GiB. So every face's size and indices are read here first.
 *  - it skips the rest of the keyword line (getline) and reads the counts after it, so counts put on
 *    that line are not read; with nothing after them the counts stayed unset. So the keyword line
 *    holds the keyword alone.
 * OpenMesh reads vertices a line at a time (blank lines skipped, words after the coordinates
 * ignored) and faces as a stream of tokens; the check reads them the same way. Comment lines inside
 * the vertex list would be read as vertices, and binary OFF's sizes cannot be checked the same way:
 * both are refused with the line and the reason. */
#include "scene/lodgen_internal.h"

#include <stdlib.h>
#include <string.h>

enum {
    OFF_LINE_MAX = 1024,
    OFF_MAX_WORDS = 16,
    OFF_MAX_FACE_SIZE = 4096, /* vertices in one face: far above any real polygon */
    OFF_MAX_FACE_EXTRAS = 4,  /* a colour after a face's indices: RGB or RGBA */
};

/* [ST][C][N][4]OFF: the keywords OpenMesh reads (nOFF, whose dimension line changes the layout, is
 * not supported). */
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

/* Keyword and counts: *nv, *nf, or an error naming the line; *line is the counts' line. */
static int off_read_header(FILE *f, const char *path, uint64_t file_size, uint64_t *line, uint64_t *nv,
                           uint64_t *nf, struct hl_error *err)
{
    char buf[OFF_LINE_MAX + 1];
    char *w[OFF_MAX_WORDS + 1];
    int got = scn_lex_line(f, buf, sizeof buf);
    *line = 1;
    if (got != 0)
        return hl_fail(err, "%s: line 1: %s", path,
                       got == -3 ? "NUL byte in the OFF header" : "no OFF keyword line (OFF, COFF, NOFF, STOFF …)");
    int k = scn_lex_words(buf, w, OFF_MAX_WORDS);
    if (k < 1 || !off_keyword(w[0]))
        return hl_fail(err, "%s: line 1: not an OFF file (the first line must start with OFF, COFF, NOFF, STOFF …)", path);
    if (k >= 2 && !strcmp(w[1], "BINARY"))
        return hl_fail(err, "%s: line 1: binary OFF is not supported (OpenMesh reads its face sizes unchecked); "
                            "convert it to text OFF, PLY or OBJ", path);
    /* OpenMesh takes the keyword line whole (getline) and reads the counts after it: counts on that
     * line are skipped, and with nothing after them it read none and pushed faces of garbage sizes
     * (2 GiB for "OFF\v0 0 0", found by fuzz_mesh_import). */
    if (k > 1)
        return hl_fail(err, "%s: line 1: words after the OFF keyword; the counts (vertices faces edges) must be on "
                            "a line of their own (OpenMesh skips the rest of the keyword line)", path);
    /* The counts on the next line that is not blank; OpenMesh reads them with >>, which skips blanks
     * but not a comment (a "# c" line there left OpenMesh with no vertex at all). */
    do {
        ++*line;
        got = scn_lex_line(f, buf, sizeof buf);
        if (got != 0)
            return hl_fail(err, "%s: line %llu: %s", path, (unsigned long long)*line,
                           got == -1 ? "OFF header ends without the vertex and face counts" : "bad OFF counts line");
        k = scn_lex_words(buf, w, OFF_MAX_WORDS);
    } while (k == 0);
    if (w[0][0] == '#')
        return hl_fail(err, "%s: line %llu: a comment before the OFF counts (OpenMesh reads the counts right after the "
                            "keyword line)", path, (unsigned long long)*line);
    if (k != 3 || !scn_lex_is_count(w[0]) || !scn_lex_is_count(w[1]) || !scn_lex_is_count(w[2]))
        return hl_fail(err, "%s: line %llu: the OFF counts must be three whole numbers (vertices faces edges)", path,
                       (unsigned long long)*line);
    *nv = strtoull(w[0], NULL, 10), *nf = strtoull(w[1], NULL, 10);
    if (*nv * 6 + *nf * 8 > file_size)
        return hl_fail(err, "%s: line %llu: %llu vertices and %llu faces cannot fit in a file of %llu bytes", path,
                       (unsigned long long)*line, (unsigned long long)*nv, (unsigned long long)*nf,
                       (unsigned long long)file_size);
    return 0;
}

/* nv vertex lines, each with at least three numbers; blank lines skipped as OpenMesh skips them. */
static int off_read_vertices(FILE *f, const char *path, uint64_t *line, uint64_t nv, struct hl_error *err)
{
    char buf[OFF_LINE_MAX + 1];
    char *w[OFF_MAX_WORDS + 1];
    for (uint64_t v = 0; v < nv;) {
        ++*line;
        int got = scn_lex_line(f, buf, sizeof buf);
        if (got == -1)
            return hl_fail(err, "%s: line %llu: the file ends after %llu of its %llu vertices", path,
                           (unsigned long long)*line, (unsigned long long)v, (unsigned long long)nv);
        if (got != 0)
            return hl_fail(err, "%s: line %llu: %s", path, (unsigned long long)*line,
                           got == -2 ? "vertex line longer than 1024 bytes" : "NUL byte");
        int k = scn_lex_words(buf, w, OFF_MAX_WORDS);
        if (k == 0)
            continue;
        if (w[0][0] == '#')
            return hl_fail(err, "%s: line %llu: comment inside the vertex list (OpenMesh would read it as vertex %llu)",
                           path, (unsigned long long)*line, (unsigned long long)v);
        if (k < 3 || !scn_lex_is_number(w[0]) || !scn_lex_is_number(w[1]) || !scn_lex_is_number(w[2]))
            return hl_fail(err, "%s: line %llu: vertex %llu: three coordinates expected", path,
                           (unsigned long long)*line, (unsigned long long)v);
        ++v;
    }
    return 0;
}

static int off_token_error(const char *path, uint64_t line, int got, uint64_t face, uint64_t nf, struct hl_error *err)
{
    if (got == -1)
        return hl_fail(err, "%s: line %llu: the file ends after %llu of its %llu faces", path,
                       (unsigned long long)line, (unsigned long long)face, (unsigned long long)nf);
    return hl_fail(err, "%s: line %llu: %s", path, (unsigned long long)line,
                   got == -2 ? "word longer than 64 bytes in the face list" : "NUL byte");
}

/* nf faces as tokens: a size 1 … OFF_MAX_FACE_SIZE, that many indices < nv, then on the same line
 * at most a colour (numbers 0 … 255). So every number OpenMesh could take for a face size, even
 * out of step, is at most max(nv, OFF_MAX_FACE_SIZE). */
static int off_read_faces(FILE *f, const char *path, uint64_t line, uint64_t nv, uint64_t nf, struct hl_error *err)
{
    char tok[65];
    int nl, got, pending = 0;
    for (uint64_t face = 0; face < nf; ++face) {
        if (!pending && (got = scn_lex_token(f, tok, sizeof tok, &line, &nl)) != 0)
            return off_token_error(path, line + 1, got, face, nf, err);
        pending = 0;
        if (!scn_lex_is_count(tok) || strtoull(tok, NULL, 10) < 1 || strtoull(tok, NULL, 10) > OFF_MAX_FACE_SIZE)
            return hl_fail(err, "%s: line %llu: face %llu: '%s' is not a face size (1 … %d vertices)", path,
                           (unsigned long long)line + 1, (unsigned long long)face, tok, OFF_MAX_FACE_SIZE);
        unsigned long n = strtoul(tok, NULL, 10);
        for (unsigned long i = 0; i < n; ++i) {
            if ((got = scn_lex_token(f, tok, sizeof tok, &line, &nl)) != 0)
                return off_token_error(path, line + 1, got, face, nf, err);
            if (!scn_lex_is_count(tok) || strtoull(tok, NULL, 10) >= nv)
                return hl_fail(err, "%s: line %llu: face %llu: '%s' is not a vertex index (0 … %llu)", path,
                               (unsigned long long)line + 1, (unsigned long long)face, tok,
                               (unsigned long long)(nv ? nv - 1 : 0));
        }
        for (int extras = 0;; ++extras) { /* the rest of the line: a colour, or nothing */
            got = scn_lex_token(f, tok, sizeof tok, &line, &nl);
            if (got == -1 && face + 1 == nf)
                return 0;
            if (got != 0)
                return off_token_error(path, line + 1, got, face + 1, nf, err);
            if (nl) {
                pending = 1;
                break;
            }
            double c = strtod(tok, NULL);
            if (extras == OFF_MAX_FACE_EXTRAS || !scn_lex_is_number(tok) || !(c >= 0 && c <= 255))
                return hl_fail(err, "%s: line %llu: face %llu: '%s' after its %lu indices is not a colour value "
                                    "(at most four numbers 0 … 255)", path, (unsigned long long)line + 1,
                               (unsigned long long)face, tok, n);
        }
    }
    return 0;
}

int scn_off_check(const char *path, uint64_t file_size, struct hl_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return hl_fail(err, "%s: cannot open", path);
    uint64_t line = 0, nv = 0, nf = 0;
    int rc = off_read_header(f, path, file_size, &line, &nv, &nf, err);
    if (rc == 0)
        rc = off_read_vertices(f, path, &line, nv, err);
    if (rc == 0)
        rc = off_read_faces(f, path, line, nv, nf, err);
    fclose(f);
    return rc;
}
