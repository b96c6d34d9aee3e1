/* scripts/70-hmdlod.rules (docs/trackers.md, DEVICES.md §3): every rule that matches a device grants
 * access only through TAG+="uaccess" (logind's ACL for the user at the active seat), none sets a
 * MODE with group or world write bits, an OWNER or a GROUP (plugdev and the like open the tracker to
 * users who are not at the seat), none runs a program (RUN), and every tracker in trk_device_table
 * and in DEVICES.md §2a has a rule. The checker is first run on bad rules, so it can fail. */
#include "test_util.h"
#include "tracking/tracking.h"

#include <ctype.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_IDS 64

struct rule_ids {
    unsigned vid[MAX_IDS], pid[MAX_IDS];
    int count;
};

struct rule_token {
    char key[64];
    char op[3];
    char value[256];
};

/* Next KEY OP "VALUE" token of a rule line; 0 at the end, −1 on a malformed token. */
static int rule_next_token(const char **cursor, struct rule_token *t)
{
    const char *p = *cursor;
    while (*p == ' ' || *p == '\t' || *p == ',')
        ++p;
    if (*p == '\0')
        return 0;
    size_t k = 0;
    while (*p && *p != '=' && *p != '!' && *p != '+' && *p != '-' && *p != ':' && *p != ' ') {
        if (k + 1 < sizeof t->key)
            t->key[k++] = *p;
        ++p;
    }
    t->key[k] = '\0';
    size_t o = 0;
    while (*p && strchr("=!+-:", *p) && o < 2)
        t->op[o++] = *p++;
    t->op[o] = '\0';
    if (k == 0 || o == 0 || *p != '"')
        return -1;
    ++p;
    size_t v = 0;
    while (*p && *p != '"') {
        if (*p == '\\' && p[1])
            ++p;
        if (v + 1 < sizeof t->value)
            t->value[v++] = *p;
        ++p;
    }
    t->value[v] = '\0';
    if (*p != '"')
        return -1;
    *cursor = p + 1;
    return 1;
}

/* Checks one rule line; prints each violation with its line number and returns their count. The
 * VID:PID of a rule that passes and grants uaccess goes into ids. */
static int rule_check_line(const char *line, int line_no, struct rule_ids *ids)
{
    const char *cursor = line;
    struct rule_token t;
    bool uaccess = false, matches_device = false;
    unsigned vid = 0, pid = 0;
    bool have_vid = false, have_pid = false;
    int bad = 0, r;
    while ((r = rule_next_token(&cursor, &t)) > 0) {
        bool assign = strcmp(t.op, "==") != 0 && strcmp(t.op, "!=") != 0;
        if (!assign && (strcmp(t.key, "ATTRS{idVendor}") == 0 || strcmp(t.key, "ATTR{idVendor}") == 0)) {
            have_vid = sscanf(t.value, "%x", &vid) == 1;
            matches_device = true;
        } else if (!assign && (strcmp(t.key, "ATTRS{idProduct}") == 0 || strcmp(t.key, "ATTR{idProduct}") == 0)) {
            have_pid = sscanf(t.value, "%x", &pid) == 1;
            matches_device = true;
        } else if (assign && strcmp(t.key, "TAG") == 0 && strcmp(t.value, "uaccess") == 0) {
            uaccess = strcmp(t.op, "+=") == 0;
        } else if (assign && strcmp(t.key, "MODE") == 0) {
            char *end;
            unsigned long mode = strtoul(t.value, &end, 8);
            if (*end != '\0' || (mode & 022) != 0) {
                fprintf(stderr, "line %d: MODE=\"%s\" lets other users write to the tracker\n", line_no, t.value);
                ++bad;
            }
        } else if (assign && (strcmp(t.key, "OWNER") == 0 || strcmp(t.key, "GROUP") == 0)) {
            fprintf(stderr, "line %d: %s=\"%s\" grants access beyond the seated user\n", line_no, t.key, t.value);
            ++bad;
        } else if (strncmp(t.key, "RUN", 3) == 0 || strncmp(t.key, "PROGRAM", 7) == 0 ||
                   strncmp(t.key, "IMPORT", 6) == 0) {
            fprintf(stderr, "line %d: %s runs a program as root\n", line_no, t.key);
            ++bad;
        }
    }
    if (r < 0) {
        fprintf(stderr, "line %d: malformed rule: %s\n", line_no, line);
        return bad + 1;
    }
    if (matches_device && !uaccess) {
        fprintf(stderr, "line %d: matches a device but lacks TAG+=\"uaccess\"\n", line_no);
        ++bad;
    }
    if (matches_device && (!have_vid || !have_pid)) {
        fprintf(stderr, "line %d: a device rule needs both idVendor and idProduct\n", line_no);
        ++bad;
    }
    if (bad == 0 && uaccess && have_vid && have_pid && ids && ids->count < MAX_IDS) {
        ids->vid[ids->count] = vid;
        ids->pid[ids->count] = pid;
        ++ids->count;
    }
    return bad;
}

/* Checks a whole rules text (comments, blank lines and backslash continuations as udev reads them);
 * returns the number of violations. */
static int rule_check_text(const char *text, struct rule_ids *ids)
{
    char line[2048];
    size_t used = 0;
    int line_no = 1, start_no = 1, bad = 0;
    for (const char *p = text;; ++p) {
        if (*p == '\n' || *p == '\0') {
            if (used > 0 && line[used - 1] == '\\' && *p == '\n') { /* continuation */
                --used;
                ++line_no;
                continue;
            }
            line[used] = '\0';
            const char *s = line;
            while (isspace((unsigned char)*s))
                ++s;
            if (*s != '\0' && *s != '#')
                bad += rule_check_line(s, start_no, ids);
            used = 0;
            start_no = ++line_no;
            if (*p == '\0')
                break;
        } else if (used + 1 < sizeof line) {
            line[used++] = *p;
        }
    }
    return bad;
}

static bool ids_have(const struct rule_ids *ids, unsigned vid, unsigned pid)
{
    for (int i = 0; i < ids->count; ++i)
        if (ids->vid[i] == vid && ids->pid[i] == pid)
            return true;
    return false;
}

/* The checker itself: each kind of bad rule is caught, a good one passes. */
static void test_checker(void)
{
    struct rule_ids ids = {0};
    CHECK(rule_check_text("ATTRS{idVendor}==\"2833\", ATTRS{idProduct}==\"0021\", TAG+=\"uaccess\"\n", &ids) == 0);
    CHECK(ids.count == 1 && ids_have(&ids, 0x2833, 0x0021));
    CHECK(rule_check_text("# ATTRS{idVendor}==\"2833\", MODE=\"0666\"\n\nLABEL=\"x\"\n", NULL) == 0);
    CHECK(rule_check_text("ATTRS{idVendor}==\"2833\", ATTRS{idProduct}==\"0021\", TAG+=\"uaccess\", MODE=\"0666\"\n",
                          NULL) == 1);
    CHECK(rule_check_text("ATTRS{idVendor}==\"2833\", ATTRS{idProduct}==\"0021\", TAG+=\"uaccess\", MODE=\"0664\", "
                          "GROUP=\"plugdev\"\n", NULL) == 2);
    CHECK(rule_check_text("ATTRS{idVendor}==\"2833\", ATTRS{idProduct}==\"0021\", MODE=\"0600\"\n", NULL) == 1);
    CHECK(rule_check_text("ATTRS{idVendor}==\"2833\", ATTRS{idProduct}==\"0021\", TAG+=\"uaccess\", "
                          "RUN+=\"/bin/chmod 666 $devnode\"\n", NULL) == 1);
    CHECK(rule_check_text("SUBSYSTEM==\"hidraw\", MODE=\"0666\"\n", NULL) == 1);
    /* A continuation joins the lines: the uaccess on the second line counts for the first. */
    ids.count = 0;
    CHECK(rule_check_text("ATTRS{idVendor}==\"054c\", ATTRS{idProduct}==\"09af\", \\\n  TAG+=\"uaccess\"\n", &ids) == 0);
    CHECK(ids.count == 1 && ids_have(&ids, 0x054c, 0x09af));
    CHECK(rule_check_text("ATTRS{idVendor}==\"2833\", TAG+=\"uaccess\"\n", NULL) == 1);
    CHECK(rule_check_text("ATTRS{idVendor}=2833\n", NULL) == 1);
}

/* VID:PIDs in the second column of DEVICES.md §2a's table; returns how many were found. */
static int devices_md_ids(const char *text, struct rule_ids *out)
{
    const char *sec = strstr(text, "### 2a.");
    if (!sec)
        return 0;
    const char *end = strstr(sec + 1, "\n### ");
    for (const char *line = sec; line && (!end || line < end); line = strchr(line, '\n')) {
        if (*line == '\n')
            ++line;
        if (*line != '|' || strncmp(line, "|---", 4) == 0)
            continue;
        const char *col = strchr(line + 1, '|'); /* the VID:PID column */
        const char *col_end = col ? strchr(col + 1, '|') : NULL;
        if (!col_end)
            continue;
        for (const char *p = col + 1; p + 9 <= col_end; ++p) {
            unsigned vid, pid;
            int n = 0;
            if (isxdigit((unsigned char)p[0]) && p[4] == ':' && sscanf(p, "%4x:%4x%n", &vid, &pid, &n) == 2 &&
                n == 9 && (p == col + 1 || !isalnum((unsigned char)p[-1])) && out->count < MAX_IDS) {
                out->vid[out->count] = vid;
                out->pid[out->count] = pid;
                ++out->count;
                p += 8;
            }
        }
    }
    return out->count;
}

static void test_shipped_rules(void)
{
    size_t size;
    const char *path = tu_source_path("scripts/70-hmdlod.rules");
    char *text = path ? tu_read_file(path, &size) : NULL;
    CHECK(text != NULL);
    if (!text)
        return;
    struct rule_ids ids = {0};
    CHECK(rule_check_text(text, &ids) == 0);
    for (size_t i = 0; i < trk_device_table_count; ++i) {
        const struct trk_device_info *d = &trk_device_table[i];
        if (!ids_have(&ids, d->vid, d->pid)) {
            fprintf(stderr, "no uaccess rule for %s %04x:%04x\n", d->name, d->vid, d->pid);
            CHECK(!"every supported tracker has a rule");
        }
    }
    free(text);

    const char *md_path = tu_shared_path("docs/DEVICES.md");
    char *md = md_path ? tu_read_file(md_path, &size) : NULL;
    if (!md)
        return; /* tu_shared_path said why */
    struct rule_ids listed = {0};
    CHECK(devices_md_ids(md, &listed) >= 12); /* Rift ×4, PSVR, Vive ×5, HDK ×2 */
    for (int i = 0; i < listed.count; ++i) {
        if (!ids_have(&ids, listed.vid[i], listed.pid[i])) {
            fprintf(stderr, "DEVICES.md §2a lists %04x:%04x, which has no uaccess rule\n", listed.vid[i],
                    listed.pid[i]);
            CHECK(!"every tracker in DEVICES.md §2a has a rule");
        }
    }
    free(md);
}

int main(void)
{
    test_checker();
    test_shipped_rules();
    return tu_finish("udev_rules");
}
