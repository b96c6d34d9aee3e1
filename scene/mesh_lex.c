/* scene/mesh_lex.c: the few text-reading steps the PLY and OFF checks (mesh_ply_check.c,
 * mesh_off_check.c) share: a bounded line, its words, a whole number, a token with its line. They
 * read byte by byte through stdio's buffer, so a check costs one pass over the file and no memory
 * that depends on it. */
#include "scene/lodgen_internal.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* What iostream >> skips in the C locale (isspace), which is how OpenMesh's readers split words: a
 * vertical tab inside "element f\vace 0" made OpenMesh read the count "ace" and loop for ever on a
 * header our split at blanks and tabs had passed (found by fuzz_mesh_import). */
const char scn_lex_blanks[] = " \t\r\n\v\f";

static int lex_is_blank(int c) { return c != '\0' && strchr(scn_lex_blanks, c) != NULL; }

int scn_lex_line(FILE *f, char *buf, size_t size)
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

int scn_lex_words(char *line, char **w, int max_words)
{
    int n = 0;
    for (char *p = strtok(line, scn_lex_blanks); p; p = strtok(NULL, scn_lex_blanks))
        if (n <= max_words)
            w[n++] = p;
    return n;
}

int scn_lex_is_count(const char *s)
{
    if (!*s)
        return 0;
    for (const char *p = s; *p; ++p)
        if (!isdigit((unsigned char)*p))
            return 0;
    return strlen(s) <= 10 && strtoull(s, NULL, 10) <= 2147483647ULL; /* OpenMesh reads an int */
}

int scn_lex_is_number(const char *s)
{
    char *end = NULL;
    (void)strtod(s, &end);
    return end != s && *end == '\0';
}

int scn_lex_token(FILE *f, char *buf, size_t size, uint64_t *line, int *newline_before)
{
    int c;
    *newline_before = 0;
    while ((c = getc(f)) != EOF && (lex_is_blank(c) || c == '\0'))
        if (c == '\n')
            ++*line, *newline_before = 1;
        else if (c == '\0')
            return -3;
    if (c == EOF)
        return -1;
    size_t n = 0;
    do {
        if (c == '\0')
            return -3;
        if (n + 1 >= size)
            return -2;
        buf[n++] = (char)c;
    } while ((c = getc(f)) != EOF && !lex_is_blank(c));
    if (c == '\n')
        ungetc(c, f); /* the newline belongs to the next token's "newline before" */
    buf[n] = '\0';
    return 0;
}
