/* scene/mesh_ply_check.c: a PLY file checked before OpenMesh 9.0 reads it (all found by
 * fuzz_mesh_import), and its triangle strips, which OpenMesh cannot read, read here.
 *  - Header: OpenMesh reads it token by token until the token "end_header" and checks only the
 *    stream's badbit: at the end of the file, or after a count that is not a number (failbit), it
 *    loops for ever. So the header must be what the PLY format says, line by line: "ply", one
 *    "format" line, then comment / obj_info / element NAME COUNT / property TYPE NAME / property
 *    list TYPE TYPE NAME lines, and a line "end_header", on which OpenMesh's loop ends. OpenMesh
 *    skips a comment line but reads obj_info's words as keywords: those may not name one.
 *  - Body: OpenMesh sizes its arrays from the element counts and each face from its list count,
 *    before it knows the file holds them; a 400-byte file claiming 2·10⁹ vertices asked for 24 GB.
 *    So every record of every element is walked here first, in the file's own encoding: the file
 *    must hold every record it announces, and no face list may be longer than PLY_MAX_LIST. Text
 *    records are one per line (as the format says), so a line- and a token-reader agree on them.
 *  - Strips: OpenMesh reads only the elements "vertex" and "face" and skips any other by the sizes
 *    of its scalars, so a "tristrips" element (Stanford's scans: one list of vertex_indices with −1
 *    between strips) gives no faces, and a list anywhere before the vertices or faces would shift
 *    what it reads for them. Since this walk reads every record anyway, it decodes the strips into
 *    triangles (struct scn_ply_strips) that the importer hands to the same path as OpenMesh's faces
 *    (mesh_validate.c: index range, welding, zero-area faces); OpenMesh still reads the vertices. A
 *    strip is one list of any length, so its count is bounded by what the file can still hold (the
 *    bytes left for binary indices; in text each index takes a digit and a blank, so at most half
 *    the bytes left) rather than by PLY_MAX_LIST: memory follows the file's size. Vertex and face
 *    elements must come before any other element with a list.
 * Anything else is refused with the line or record and the reason. */
#include "scene/lodgen_internal.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

enum {
    PLY_HEADER_MAX_LINES = 4096,
    PLY_LINE_MAX = 1024,
    PLY_MAX_WORDS = 6,
    PLY_MAX_ELEMENTS = 16,
    PLY_MAX_PROPS = 64,
    PLY_MAX_LIST = 4096, /* items in one list (vertices of a face): far above any real polygon */
    PLY_RECORD_LINE_MAX = 65536,
    PLY_WORD_MAX = 1024, /* one value of a text strip record */
};

enum ply_format { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE };

struct ply_type {
    const char *name;
    int bytes, is_int, is_signed;
};
static const struct ply_type ply_types[] = {
    {"char", 1, 1, 1},    {"uchar", 1, 1, 0},   {"short", 2, 1, 1},   {"ushort", 2, 1, 0},
    {"int", 4, 1, 1},     {"uint", 4, 1, 0},    {"float", 4, 0, 1},   {"double", 8, 0, 1},
    {"int8", 1, 1, 1},    {"uint8", 1, 1, 0},   {"int16", 2, 1, 1},   {"uint16", 2, 1, 0},
    {"int32", 4, 1, 1},   {"uint32", 4, 1, 0},  {"float32", 4, 0, 1}, {"float64", 8, 0, 1},
};

struct ply_prop {
    const struct ply_type *type;       /* scalar type, or a list's item type */
    const struct ply_type *count_type; /* NULL for a scalar */
    int is_indices;                    /* named vertex_indices or vertex_index */
};
struct ply_element {
    char name[64];
    uint64_t count;
    int line;       /* of its header line */
    int strip_prop; /* the vertex_indices list of a "tristrips" element, else −1 */
    int prop_count;
    struct ply_prop props[PLY_MAX_PROPS];
};
struct ply_layout {
    enum ply_format format;
    int element_count;
    struct ply_element elements[PLY_MAX_ELEMENTS];
};

static const struct ply_type *ply_find_type(const char *w)
{
    for (size_t i = 0; i < sizeof ply_types / sizeof ply_types[0]; ++i)
        if (!strcmp(w, ply_types[i].name))
            return &ply_types[i];
    return NULL;
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

/* One header line's words (line n) into the layout: NULL, or why the line is refused. */
static const char *ply_header_words(char **w, int k, int n, struct ply_layout *lay)
{
    if (!strcmp(w[0], "comment") || !strcmp(w[0], "obj_info"))
        return NULL;
    if (!strcmp(w[0], "format")) {
        if (k != 3 || !ply_is_version(w[2]))
            return "format must be \"format ascii|binary_little_endian|binary_big_endian VERSION\" (VERSION a "
                   "number such as 1.0)";
        if (!strcmp(w[1], "ascii"))
            lay->format = PLY_ASCII;
        else if (!strcmp(w[1], "binary_little_endian"))
            lay->format = PLY_BINARY_LE;
        else if (!strcmp(w[1], "binary_big_endian"))
            lay->format = PLY_BINARY_BE;
        else
            return "format must be ascii, binary_little_endian or binary_big_endian";
        return NULL;
    }
    if (!strcmp(w[0], "element")) {
        if (k != 3 || !scn_lex_is_count(w[2]))
            return "element must be \"element NAME COUNT\" (COUNT a whole number)";
        if (lay->element_count == PLY_MAX_ELEMENTS)
            return "more than 16 elements";
        struct ply_element *e = &lay->elements[lay->element_count++];
        snprintf(e->name, sizeof e->name, "%s", w[1]);
        e->count = strtoull(w[2], NULL, 10);
        e->line = n;
        e->strip_prop = -1;
        return NULL;
    }
    if (!strcmp(w[0], "property")) {
        struct ply_prop p = {NULL, NULL, 0};
        if (k == 3)
            p.type = ply_find_type(w[1]);
        else if (k == 5 && !strcmp(w[1], "list"))
            p.count_type = ply_find_type(w[2]), p.type = ply_find_type(w[3]);
        p.is_indices = !strcmp(w[k - 1], "vertex_indices") || !strcmp(w[k - 1], "vertex_index");
        if (!p.type || (k == 5 && !p.count_type))
            return "property must be \"property TYPE NAME\" or \"property list TYPE TYPE NAME\"";
        if (p.count_type && !p.count_type->is_int)
            return "a list's count type must be an integer type";
        if (lay->element_count == 0)
            return "property before any element";
        struct ply_element *e = &lay->elements[lay->element_count - 1];
        if (e->prop_count == PLY_MAX_PROPS)
            return "more than 64 properties in one element";
        e->props[e->prop_count++] = p;
        return NULL;
    }
    return "unknown PLY header keyword";
}

/* OpenMesh skips the rest of a "comment" line but reads an "obj_info" line's words as header keywords,
 * one by one (fuzz_mesh_import: "obj_info … element tristrips \"perty" declared an element whose count
 * failed to read, and its header loop spun for ever). So an obj_info line may not name element,
 * property or end_header before a word "comment" (after which OpenMesh skips the line): the keyword
 * named, or NULL (and for every other line). line is the whole line: scn_lex_words keeps only the
 * first few words. */
static const char *ply_obj_info_keyword(const char *line)
{
    static const char *const keywords[] = {"element", "property", "end_header"};
    const char *first = line + strspn(line, scn_lex_blanks);
    if (strncmp(first, "obj_info", 8) || (first[8] && !strchr(scn_lex_blanks, first[8])))
        return NULL;
    char copy[PLY_LINE_MAX + 1], *save = NULL;
    snprintf(copy, sizeof copy, "%s", first + 8);
    for (char *w = strtok_r(copy, scn_lex_blanks, &save); w; w = strtok_r(NULL, scn_lex_blanks, &save)) {
        if (!strcmp(w, "comment"))
            return NULL;
        for (int i = 0; i < 3; ++i)
            if (!strcmp(w, keywords[i]))
                return keywords[i];
    }
    return NULL;
}

/* The header up to and including end_header: 0 with the layout and *line at end_header's line. */
static int ply_read_header(FILE *f, const char *path, struct ply_layout *lay, uint64_t *line, struct hl_error *err)
{
    char buf[PLY_LINE_MAX + 1];
    int have_format = 0;
    for (int n = 1; n <= PLY_HEADER_MAX_LINES; ++n) {
        int got = scn_lex_line(f, buf, sizeof buf);
        if (got == -1)
            return hl_fail(err, "%s: line %d: PLY header ends without an end_header line", path, n);
        if (got == -2)
            return hl_fail(err, "%s: line %d: PLY header line longer than %d bytes", path, n, PLY_LINE_MAX);
        if (got == -3)
            return hl_fail(err, "%s: line %d: NUL byte in the PLY header", path, n);
        const char *info_keyword = ply_obj_info_keyword(buf);
        if (info_keyword)
            return hl_fail(err, "%s: line %d: an obj_info line naming '%s' (OpenMesh reads obj_info's words as "
                           "header keywords)", path, n, info_keyword);
        char *w[PLY_MAX_WORDS + 1];
        int k = scn_lex_words(buf, w, PLY_MAX_WORDS);
        const char *why;
        if (n == 1)
            why = k == 1 && !strcmp(w[0], "ply") ? NULL : "not a PLY file (the first line must be \"ply\")";
        else if (k == 0)
            why = "empty line in the PLY header";
        else if (!strcmp(w[0], "end_header")) {
            if (k != 1)
                why = "end_header followed by more words";
            else if (!have_format)
                why = "no format line before end_header";
            else {
                *line = (uint64_t)n;
                return 0;
            }
        } else {
            have_format |= !strcmp(w[0], "format");
            why = ply_header_words(w, k, n, lay);
        }
        if (why)
            return hl_fail(err, "%s: line %d: %s", path, n, why);
    }
    return hl_fail(err, "%s: PLY header longer than %d lines", path, PLY_HEADER_MAX_LINES);
}

/* A binary integer of `t` at the file position, in the file's byte order: 0, or −1 at the end. */
static int ply_read_binary_int(FILE *f, const struct ply_type *t, int big_endian, int64_t *out)
{
    unsigned char b[4];
    if (fread(b, 1, (size_t)t->bytes, f) != (size_t)t->bytes)
        return -1;
    uint32_t u = 0;
    for (int i = 0; i < t->bytes; ++i)
        u |= (uint32_t)b[big_endian ? t->bytes - 1 - i : i] << (8 * i);
    if (t->is_signed && t->bytes < 4 && (u >> (8 * t->bytes - 1)))
        *out = (int64_t)u - ((int64_t)1 << (8 * t->bytes));
    else
        *out = t->is_signed ? (int64_t)(int32_t)u : (int64_t)u;
    return 0;
}

static int ply_record_error(const char *path, const struct ply_element *e, uint64_t r, const char *why,
                            struct hl_error *err)
{
    return hl_fail(err, "%s: %s %llu (of %llu): %s", path, e->name, (unsigned long long)r,
                   (unsigned long long)e->count, why);
}

/* Finds each "tristrips" element's index list and checks the order OpenMesh needs: it skips an
 * element it does not read by its scalars' sizes, one word or value per property, so after a list
 * there it would read the vertices or faces from the wrong place. *vertex_count: the vertices the
 * strips may name (OpenMesh adds one per record of every "vertex" element). */
static int ply_layout_check(const char *path, struct ply_layout *lay, uint64_t *vertex_count, struct hl_error *err)
{
    const struct ply_element *listed = NULL; /* the first element OpenMesh cannot skip */
    *vertex_count = 0;
    for (int i = 0; i < lay->element_count; ++i) {
        struct ply_element *e = &lay->elements[i];
        int is_vertex = !strcmp(e->name, "vertex"), known = is_vertex || !strcmp(e->name, "face");
        if (known && listed)
            return hl_fail(err, "%s: line %d: element %s after element %s, whose lists OpenMesh cannot skip: the "
                           "vertex and face elements must come first", path, e->line, e->name, listed->name);
        if (is_vertex)
            *vertex_count += e->count;
        int has_list = 0;
        for (int p = 0; p < e->prop_count; ++p) {
            const struct ply_prop *pr = &e->props[p];
            has_list |= pr->count_type != NULL;
            if (!strcmp(e->name, "tristrips") && pr->count_type && pr->is_indices && e->strip_prop < 0) {
                if (!pr->type->is_int)
                    return hl_fail(err, "%s: line %d: element tristrips: its vertex_indices must be a list of "
                                   "integers", path, e->line);
                e->strip_prop = p;
            }
        }
        if (!known && has_list && !listed)
            listed = e;
    }
    return 0;
}

/* ---- triangle strips ------------------------------------------------------------------------------
 * Decoded as OpenGL draws GL_TRIANGLE_STRIP and as MeshLab (VCG's PLY importer) reads Stanford's
 * tristrips: in one strip v0 v1 v2 …, triangle k is (v[k], v[k+1], v[k+2]) for even k and
 * (v[k+1], v[k], v[k+2]) for odd k, so that every triangle faces the way the first one does. −1 ends
 * a strip; the next index starts a new one, with k from 0 again; each record starts one too. A
 * triangle with a repeated index is one of the strip's joins or turns, not a surface: it is left
 * out, but still counts for k. */

struct ply_strip_state {
    struct scn_ply_strips *out; /* NULL: checked only */
    uint64_t vertex_count;
    uint32_t prev[2]; /* the strip's last two indices, older first */
    uint64_t run;     /* indices since the strip began */
};
enum { STRIP_OK, STRIP_NEGATIVE, STRIP_MISSING_VERTEX, STRIP_TOO_MANY, STRIP_NO_MEMORY };

void scn_ply_strips_free(struct scn_ply_strips *s)
{
    if (!s)
        return;
    free(s->indices);
    memset(s, 0, sizeof *s);
}

static int strip_push(struct scn_ply_strips *s, uint32_t a, uint32_t b, uint32_t c)
{
    if (s->triangle_count == s->triangle_cap) {
        /* the soup holds at most UINT32_MAX / 3 triangles (32-bit indices): no use reading more */
        if (s->triangle_cap >= UINT32_MAX / 6)
            return STRIP_TOO_MANY;
        uint32_t cap = s->triangle_cap ? 2 * s->triangle_cap : 1024;
        uint32_t *idx = realloc(s->indices, (size_t)cap * 3 * sizeof *idx);
        if (!idx)
            return STRIP_NO_MEMORY;
        s->indices = idx, s->triangle_cap = cap;
    }
    uint32_t *t = s->indices + 3 * (size_t)s->triangle_count++;
    t[0] = a, t[1] = b, t[2] = c;
    return STRIP_OK;
}

/* One index of a strip: STRIP_OK, or what is wrong with it. */
static int strip_index(struct ply_strip_state *s, int64_t v)
{
    if (s->out)
        s->out->items++;
    if (v == -1) {
        s->run = 0;
        return STRIP_OK;
    }
    if (v < 0)
        return STRIP_NEGATIVE;
    if ((uint64_t)v >= s->vertex_count || v >= (int64_t)UINT32_MAX) /* the soup's indices are 32-bit */
        return STRIP_MISSING_VERTEX;
    uint32_t a = s->prev[0], b = s->prev[1], c = (uint32_t)v;
    s->prev[0] = b, s->prev[1] = c;
    if (s->run++ < 2)
        return STRIP_OK;
    if ((s->run - 3) & 1) { /* odd k: reversed, to face the same way */
        uint32_t t = a;
        a = b, b = t;
    }
    if (a == b || b == c || a == c || !s->out)
        return STRIP_OK;
    return strip_push(s->out, a, b, c);
}

/* Why index `item` (its value v) of a strip was refused, into buf. */
static const char *strip_why(int code, uint64_t item, int64_t v, uint64_t vertex_count, char *buf, size_t size)
{
    if (code == STRIP_NEGATIVE)
        snprintf(buf, size, "index %llu is %lld (only -1, which ends a strip, may be negative)",
                 (unsigned long long)item, (long long)v);
    else if (code == STRIP_MISSING_VERTEX)
        snprintf(buf, size, "index %llu names vertex %lld, which does not exist (%llu vertices)",
                 (unsigned long long)item, (long long)v, (unsigned long long)vertex_count);
    else if (code == STRIP_TOO_MANY)
        snprintf(buf, size, "more triangles than 32-bit indices hold");
    else
        snprintf(buf, size, "out of memory for its triangles");
    return buf;
}

/* ---- binary ---------------------------------------------------------------------------------------- */

/* A binary strip list of n items of `t` at the file position; the count is bounded by the bytes the
 * file still holds before anything is read. NULL, or why (in buf). */
static const char *ply_binary_strip(FILE *f, const struct ply_type *t, int64_t n, int big_endian, uint64_t size,
                                    struct ply_strip_state *st, char *buf, size_t buf_size)
{
    off_t at = ftello(f);
    uint64_t left = at >= 0 && (uint64_t)at <= size ? size - (uint64_t)at : 0;
    if ((uint64_t)n > left / (uint64_t)t->bytes) {
        snprintf(buf, buf_size, "a strip of %lld indices of %d bytes, but the file ends %llu bytes on", (long long)n,
                 t->bytes, (unsigned long long)left);
        return buf;
    }
    st->run = 0;
    for (int64_t i = 0; i < n; ++i) {
        int64_t v;
        if (ply_read_binary_int(f, t, big_endian, &v) != 0)
            return "the file ends inside this record";
        int code = strip_index(st, v);
        if (code != STRIP_OK)
            return strip_why(code, (uint64_t)i, v, st->vertex_count, buf, buf_size);
    }
    return NULL;
}

/* One element's records in binary. Fixed-size records are skipped in one seek; strips are read. */
static int ply_walk_binary(FILE *f, const char *path, const struct ply_element *e, int big_endian, uint64_t size,
                           struct ply_strip_state *st, struct hl_error *err)
{
    uint64_t fixed = 0;
    int has_list = 0;
    for (int p = 0; p < e->prop_count; ++p)
        has_list |= e->props[p].count_type != NULL, fixed += (uint64_t)e->props[p].type->bytes;
    if (e->count > 0 && e->prop_count == 0) /* OpenMesh still adds a vertex per record: 0 bytes each */
        return ply_record_error(path, e, 0, "an element with records but no properties", err);
    if (!has_list) {
        off_t at = ftello(f);
        uint64_t remaining = at >= 0 && (uint64_t)at <= size ? size - (uint64_t)at : 0;
        if (e->count > 0 && fixed > remaining / e->count)
            return ply_record_error(path, e, remaining / (fixed ? fixed : 1),
                                    "the file ends before this element's last record", err);
        return fseeko(f, (off_t)(fixed * e->count), SEEK_CUR) == 0 ? 0 : hl_fail(err, "%s: cannot seek", path);
    }
    char why[160];
    for (uint64_t r = 0; r < e->count; ++r)
        for (int p = 0; p < e->prop_count; ++p) {
            const struct ply_prop *pr = &e->props[p];
            int64_t n = 1;
            if (pr->count_type && ply_read_binary_int(f, pr->count_type, big_endian, &n) != 0)
                return ply_record_error(path, e, r, "the file ends inside this record", err);
            if (p == e->strip_prop) {
                const char *bad = n < 0 ? "a strip of negative length" :
                                          ply_binary_strip(f, pr->type, n, big_endian, size, st, why, sizeof why);
                if (bad)
                    return ply_record_error(path, e, r, bad, err);
                continue;
            }
            if (n < 0 || n > PLY_MAX_LIST)
                return ply_record_error(path, e, r, "a list longer than 4096 items, or of negative length", err);
            if (n > 0 && fseeko(f, (off_t)(n * pr->type->bytes), SEEK_CUR) != 0)
                return hl_fail(err, "%s: cannot seek", path);
        }
    /* fseeko past the end succeeds; the position says whether the records were all there */
    off_t at = ftello(f);
    if (fseeko(f, 0, SEEK_END) != 0)
        return hl_fail(err, "%s: cannot seek", path);
    if (ftello(f) < at)
        return ply_record_error(path, e, e->count - 1, "the file ends inside this record", err);
    return fseeko(f, at, SEEK_SET) == 0 ? 0 : hl_fail(err, "%s: cannot seek", path);
}

/* ---- text ------------------------------------------------------------------------------------------ */

/* One text record: its words must be exactly its properties' values, lists with their counts. */
static const char *ply_text_record(char **w, int k, const struct ply_element *e)
{
    int i = 0;
    for (int p = 0; p < e->prop_count; ++p) {
        long n = 1;
        if (e->props[p].count_type) {
            if (i >= k || !scn_lex_is_count(w[i]) || (n = strtol(w[i], NULL, 10)) > PLY_MAX_LIST)
                return "a list's count must be a whole number 0 … 4096";
            ++i;
        }
        for (long j = 0; j < n; ++j, ++i)
            if (i >= k || !scn_lex_is_number(w[i]))
                return i >= k ? "fewer values than its properties" : "a value that is not a number";
    }
    return i == k ? NULL : "more values than its properties";
}

/* The next word of the current line into buf: 1; 0 at the line's end (its newline read); −1 at the
 * end of the file; −2 a word longer than buf; −3 a NUL byte. Blanks are iostream's (scn_lex_blanks). */
static int ply_word(FILE *f, char *buf, size_t size)
{
    int c;
    while ((c = getc(f)) != EOF && c != '\n' && c != '\0' && strchr(scn_lex_blanks, c))
        ;
    if (c == EOF)
        return -1;
    if (c == '\n')
        return 0;
    size_t n = 0;
    do {
        if (c == '\0')
            return -3;
        if (n + 1 >= size)
            return -2;
        buf[n++] = (char)c;
    } while ((c = getc(f)) != EOF && (c == '\0' || !strchr(scn_lex_blanks, c)));
    if (c == '\n')
        ungetc(c, f); /* the line's end, for the next call */
    buf[n] = '\0';
    return 1;
}

/* Why a word could not be read where a value was due. */
static const char *ply_word_why(int got)
{
    return got == -1 ? "the file ends inside this record" : got == -2 ? "a value longer than 1023 bytes" :
           got == -3 ? "NUL byte" : "fewer values than its properties";
}

/* One text record of an element holding a strip, read word by word: a strip is one list of any
 * length, more than a line buffer should hold. Its count is bounded by the bytes left (each index is
 * a digit and a blank at least); the record still ends with its line. NULL, or why (maybe in buf). */
static const char *ply_text_strip_record(FILE *f, const struct ply_element *e, uint64_t size,
                                         struct ply_strip_state *st, char *word, char *buf, size_t buf_size)
{
    int got = ply_word(f, word, PLY_WORD_MAX);
    if (got == -1)
        return "the file ends before this record";
    for (int p = 0; p < e->prop_count; ++p) {
        const struct ply_prop *pr = &e->props[p];
        int strip = p == e->strip_prop;
        long n = 1;
        if (pr->count_type) {
            if (got != 1)
                return ply_word_why(got);
            if (!scn_lex_is_count(word))
                return "a list's count must be a whole number";
            n = strtol(word, NULL, 10);
            off_t at = ftello(f);
            uint64_t left = at >= 0 && (uint64_t)at <= size ? size - (uint64_t)at : 0;
            if (strip && (uint64_t)n > left / 2) {
                snprintf(buf, buf_size, "a strip of %ld indices, but the file ends %llu bytes on", n,
                         (unsigned long long)left);
                return buf;
            }
            if (!strip && n > PLY_MAX_LIST)
                return "a list's count must be a whole number 0 … 4096";
            got = ply_word(f, word, PLY_WORD_MAX);
        }
        st->run = 0;
        for (long j = 0; j < n; ++j, got = ply_word(f, word, PLY_WORD_MAX)) {
            if (got != 1)
                return ply_word_why(got);
            if (!strip) {
                if (!scn_lex_is_number(word))
                    return "a value that is not a number";
                continue;
            }
            char *end = NULL;
            errno = 0;
            long long v = strtoll(word, &end, 10);
            if (end == word || *end || errno) {
                snprintf(buf, buf_size, "index %ld: '%.40s' is not a whole number", j, word);
                return buf;
            }
            int code = strip_index(st, v);
            if (code != STRIP_OK)
                return strip_why(code, (uint64_t)j, v, st->vertex_count, buf, buf_size);
        }
    }
    if (got == 1)
        return "more values than its properties";
    return got == -1 ? "the file ends before this record's newline" : got < 0 ? ply_word_why(got) : NULL;
}

/* One element's records in text, one record per line, counting lines from *line. */
static int ply_walk_text(FILE *f, const char *path, const struct ply_element *e, uint64_t size, uint64_t *line,
                         char *buf, char **w, struct ply_strip_state *st, struct hl_error *err)
{
    char why[160];
    for (uint64_t r = 0; r < e->count; ++r) {
        ++*line;
        const char *bad;
        if (e->strip_prop >= 0) {
            bad = ply_text_strip_record(f, e, size, st, buf, why, sizeof why);
        } else {
            int got = scn_lex_line(f, buf, PLY_RECORD_LINE_MAX + 1);
            bad = got == -1 ? "the file ends before this record" :
                  got == -2 ? "line longer than 65536 bytes" :
                  got == -3 ? "NUL byte" : ply_text_record(w, scn_lex_words(buf, w, 4 * PLY_MAX_LIST), e);
        }
        if (bad)
            return hl_fail(err, "%s: line %llu: %s %llu (of %llu): %s", path, (unsigned long long)*line, e->name,
                           (unsigned long long)r, (unsigned long long)e->count, bad);
    }
    return 0;
}

int scn_ply_check(const char *path, struct scn_ply_strips *strips, struct hl_error *err)
{
    if (strips)
        memset(strips, 0, sizeof *strips);
    uint64_t size = 0;
    FILE *f = hl_file_open_read(path, &size, err);
    if (!f)
        return -1;
    struct ply_layout *lay = calloc(1, sizeof *lay);
    char *buf = malloc(PLY_RECORD_LINE_MAX + 1);
    char **w = malloc((4 * PLY_MAX_LIST + 1) * sizeof *w);
    uint64_t line = 0;
    struct ply_strip_state st = {strips, 0, {0, 0}, 0};
    int rc = lay && buf && w ? ply_read_header(f, path, lay, &line, err) : hl_fail(err, "%s: out of memory", path);
    if (rc == 0)
        rc = ply_layout_check(path, lay, &st.vertex_count, err);
    for (int i = 0; rc == 0 && i < lay->element_count; ++i) {
        const struct ply_element *e = &lay->elements[i];
        if (strips && e->strip_prop >= 0)
            strips->elements++;
        if (lay->format == PLY_ASCII)
            rc = ply_walk_text(f, path, e, size, &line, buf, w, &st, err);
        else
            rc = ply_walk_binary(f, path, e, lay->format == PLY_BINARY_BE, size, &st, err);
    }
    free(w);
    free(buf);
    free(lay);
    fclose(f);
    if (rc != 0)
        scn_ply_strips_free(strips);
    return rc;
}
