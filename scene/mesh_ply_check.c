/* scene/mesh_ply_check.c: a PLY file checked before OpenMesh 9.0 reads it (all found by
 * fuzz_mesh_import).
 *  - Header: OpenMesh reads it token by token until the token "end_header" and checks only the
 *    stream's badbit: at the end of the file, or after a count that is not a number (failbit), it
 *    loops for ever. So the header must be what the PLY format says, line by line: "ply", one
 *    "format" line, then comment / obj_info / element NAME COUNT / property TYPE NAME / property
 *    list TYPE TYPE NAME lines, and a line "end_header", on which OpenMesh's loop ends.
 *  - Body: OpenMesh sizes its arrays from the element counts and each face from its list count,
 *    before it knows the file holds them; a 400-byte file claiming 2·10⁹ vertices asked for 24 GB.
 *    So every record of every element is walked here first, in the file's own encoding: the file
 *    must hold every record it announces, and no list may be longer than PLY_MAX_LIST. Text
 *    records are one per line (as the format says), so a line- and a token-reader agree on them.
 * Anything else is refused with the line or record and the reason. */
#include "scene/lodgen_internal.h"

#include <ctype.h>
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
};
struct ply_element {
    char name[64];
    uint64_t count;
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

/* One header line's words into the layout: NULL, or why the line is refused. */
static const char *ply_header_words(char **w, int k, struct ply_layout *lay)
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
        return NULL;
    }
    if (!strcmp(w[0], "property")) {
        struct ply_prop p = {NULL, NULL};
        if (k == 3)
            p.type = ply_find_type(w[1]);
        else if (k == 5 && !strcmp(w[1], "list"))
            p.count_type = ply_find_type(w[2]), p.type = ply_find_type(w[3]);
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
            why = ply_header_words(w, k, lay);
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

/* One element's records in binary. Fixed-size records are skipped in one seek. */
static int ply_walk_binary(FILE *f, const char *path, const struct ply_element *e, int big_endian,
                           uint64_t remaining, struct hl_error *err)
{
    uint64_t fixed = 0;
    int has_list = 0;
    for (int p = 0; p < e->prop_count; ++p)
        has_list |= e->props[p].count_type != NULL, fixed += (uint64_t)e->props[p].type->bytes;
    if (e->count > 0 && e->prop_count == 0) /* OpenMesh still adds a vertex per record: 0 bytes each */
        return ply_record_error(path, e, 0, "an element with records but no properties", err);
    if (!has_list) {
        if (e->count > 0 && fixed > remaining / e->count)
            return ply_record_error(path, e, remaining / (fixed ? fixed : 1),
                                    "the file ends before this element's last record", err);
        return fseeko(f, (off_t)(fixed * e->count), SEEK_CUR) == 0 ? 0 : hl_fail(err, "%s: cannot seek", path);
    }
    for (uint64_t r = 0; r < e->count; ++r)
        for (int p = 0; p < e->prop_count; ++p) {
            const struct ply_prop *pr = &e->props[p];
            int64_t n = 1;
            if (pr->count_type && ply_read_binary_int(f, pr->count_type, big_endian, &n) != 0)
                return ply_record_error(path, e, r, "the file ends inside this record", err);
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

/* One element's records in text, one record per line, counting lines from *line. */
static int ply_walk_text(FILE *f, const char *path, const struct ply_element *e, uint64_t *line, char *buf,
                         char **w, struct hl_error *err)
{
    for (uint64_t r = 0; r < e->count; ++r) {
        ++*line;
        int got = scn_lex_line(f, buf, PLY_RECORD_LINE_MAX + 1);
        if (got != 0)
            return hl_fail(err, "%s: line %llu: %s %llu (of %llu): %s", path, (unsigned long long)*line, e->name,
                           (unsigned long long)r, (unsigned long long)e->count,
                           got == -1 ? "the file ends before this record" :
                           got == -2 ? "line longer than 65536 bytes" : "NUL byte");
        int k = scn_lex_words(buf, w, 4 * PLY_MAX_LIST);
        const char *why = ply_text_record(w, k, e);
        if (why)
            return hl_fail(err, "%s: line %llu: %s %llu (of %llu): %s", path, (unsigned long long)*line, e->name,
                           (unsigned long long)r, (unsigned long long)e->count, why);
    }
    return 0;
}

int scn_ply_check(const char *path, struct hl_error *err)
{
    uint64_t size = 0;
    FILE *f = hl_file_open_read(path, &size, err);
    if (!f)
        return -1;
    struct ply_layout *lay = calloc(1, sizeof *lay);
    char *buf = malloc(PLY_RECORD_LINE_MAX + 1);
    char **w = malloc((4 * PLY_MAX_LIST + 1) * sizeof *w);
    uint64_t line = 0;
    int rc = lay && buf && w ? ply_read_header(f, path, lay, &line, err) : hl_fail(err, "%s: out of memory", path);
    for (int i = 0; rc == 0 && i < lay->element_count; ++i) {
        const struct ply_element *e = &lay->elements[i];
        if (lay->format == PLY_ASCII)
            rc = ply_walk_text(f, path, e, &line, buf, w, err);
        else {
            off_t at = ftello(f);
            rc = ply_walk_binary(f, path, e, lay->format == PLY_BINARY_BE, at < 0 ? 0 : size - (uint64_t)at, err);
        }
    }
    free(w);
    free(buf);
    free(lay);
    fclose(f);
    return rc;
}
