/* Output files (base.h, "output files") and the faults around them (docs/HARD_CASES.md, "Faults"):
 * every write lands whole or not at all, a symlink planted at an output's name is replaced and its
 * target left alone, a symlink planted where the program makes a folder is refused, and a full disk
 * (tests/enospc_shim.c, preloaded into a child of this program) is an error naming the file, leaves
 * no temporary and no half file, and leaves a recording readable up to its last complete record. */
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/base.h"
#include "render/render.h"
#include "replay/replay.h"
#include "tests/test_util.h"
#include "tracking/tracking.h"

static char dir[256];

static const char *at(const char *name)
{
    static char path[2][512];
    static int k;
    k ^= 1;
    snprintf(path[k], sizeof path[k], "%s/%s", dir, name);
    return path[k];
}

static void put(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static int same_text(const char *path, const char *text)
{
    size_t n = 0;
    char *b = tu_read_file(path, &n);
    int same = b && n == strlen(text) && memcmp(b, text, n) == 0;
    free(b);
    return same;
}

static int is_regular(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Entries of folder d whose name holds ".tmp.": hl_out's temporaries, which must never stay. */
static int temporaries_in(const char *d)
{
    DIR *dd = opendir(d);
    int n = 0;
    for (struct dirent *e; dd && (e = readdir(dd));)
        if (strstr(e->d_name, ".tmp.")) {
            fprintf(stderr, "  stray temporary: %s/%s\n", d, e->d_name);
            ++n;
        }
    if (dd)
        closedir(dd);
    return n;
}

static void test_out_basics(void)
{
    struct hl_error err = {""};
    struct hl_out o;
    CHECK(hl_out_open(&o, at("a.txt"), &err) == 0);
    fputs("hello\n", o.f);
    CHECK(access(at("a.txt"), F_OK) != 0); /* nothing under the final name until the commit */
    CHECK(hl_out_commit(&o, &err) == 0);
    CHECK(same_text(at("a.txt"), "hello\n"));
    struct stat st;
    mode_t mask = umask(022);
    umask(mask);
    CHECK(stat(at("a.txt"), &st) == 0 && (st.st_mode & 0777) == (0644 & ~mask));
    /* Abort: the previous file stays whole. */
    CHECK(hl_out_open(&o, at("a.txt"), &err) == 0);
    fputs("half", o.f);
    hl_out_abort(&o);
    CHECK(same_text(at("a.txt"), "hello\n"));
    /* A folder at the name: the rename fails, named, and the temporary goes. */
    mkdir(at("d"), 0700);
    CHECK(hl_out_write_all(at("d"), "x", 1, &err) != 0 && strstr(err.msg, "/d: cannot rename into place"));
    /* A missing folder: one message naming the path. */
    CHECK(hl_out_write_all(at("none/x"), "x", 1, &err) != 0 && strstr(err.msg, "none/x: cannot create"));
    CHECK(temporaries_in(dir) == 0);
    rmdir(at("d"));
}

/* A planted symlink at an output's name: replaced by a regular file, the target untouched. */
static void plant(const char *name, const char *victim)
{
    unlink(at(name));
    CHECK(symlink(victim, at(name)) == 0);
}
static void check_planted(const char *name, const char *victim, const char *what)
{
    int ok = is_regular(at(name)) && same_text(victim, "victim\n");
    if (!ok)
        fprintf(stderr, "  %s: the planted link at %s was followed\n", what, name);
    CHECK(ok);
}

static void test_planted_links(void)
{
    char victim[512];
    snprintf(victim, sizeof victim, "%s/victim.txt", dir);
    put(victim, "victim\n");
    struct hl_error err = {""};

    plant("w.txt", victim);
    CHECK(hl_out_write_all(at("w.txt"), "new\n", 4, &err) == 0);
    check_planted("w.txt", victim, "hl_out_write_all");

    double t[2] = {0.0, 1.0};
    hl_quatd q[2] = {hl_q_identity(), hl_q_identity()};
    struct rpl_trace tr;
    memset(&tr, 0, sizeof tr);
    tr.count = 2, tr.time_s = t, tr.orientation = q;
    plant("trace.csv", victim);
    CHECK(rpl_trace_write_csv(&tr, at("trace.csv"), &err) == 0);
    check_planted("trace.csv", victim, "trace");

    uint8_t rgba[4 * 4 * 4];
    memset(rgba, 200, sizeof rgba);
    plant("f.png", victim);
    CHECK(rnd_png_write(at("f.png"), rgba, 4, 4, &err) == 0);
    check_planted("f.png", victim, "png");

    plant("rec.raw", victim);
    struct trk_recording *rec = trk_recording_create(at("rec.raw"), TRK_DEVICE_HDK, 1, 2, "test", &err);
    CHECK(rec != NULL);
    uint8_t report[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    CHECK(rec && trk_recording_append(rec, 5, report, sizeof report, &err) == 0);
    CHECK(trk_recording_close(rec, 1, &err) == 0);
    check_planted("rec.raw", victim, "raw recording");

    /* Folders the program makes: a link there is refused, a file there too, a real one is fine. */
    CHECK(hl_dir_make(at("made"), &err) == 0 && hl_dir_make(at("made"), &err) == 0);
    char elsewhere[512];
    snprintf(elsewhere, sizeof elsewhere, "%s/elsewhere", dir);
    mkdir(elsewhere, 0700);
    CHECK(symlink(elsewhere, at("linked")) == 0);
    CHECK(hl_dir_make(at("linked"), &err) != 0 && strstr(err.msg, "linked: is a symbolic link"));
    CHECK(hl_dir_make(at("victim.txt"), &err) != 0 && strstr(err.msg, "victim.txt: exists and is not a folder"));
    CHECK(same_text(victim, "victim\n"));
    CHECK(temporaries_in(dir) == 0);
}

/* ---- disk full: children of this program with the shim preloaded ------------------------------ */

enum { RECORDS = 40, REPORT = 24 };

/* The child's side: one writer against the full disk; exit 0 when it succeeded, 1 with the message on
 * stderr when it failed. */
static int child(const char *what, const char *path)
{
    struct hl_error err = {""};
    int rc = 0;
    if (!strcmp(what, "recording")) {
        struct trk_recording *rec = trk_recording_create(path, TRK_DEVICE_HDK, 1, 2, "full", &err);
        if (!rec) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        uint8_t report[REPORT];
        for (int i = 0; i < RECORDS && rc == 0; ++i) {
            memset(report, i, sizeof report);
            rc = trk_recording_append(rec, (int64_t)i * 1000, report, sizeof report, &err);
        }
        if (rc != 0)
            fprintf(stderr, "%s\n", err.msg);
        struct hl_error cerr;
        if (trk_recording_close(rec, 1, &cerr) != 0 && rc == 0)
            fprintf(stderr, "%s\n", cerr.msg), rc = -1;
        return rc ? 1 : 0;
    }
    if (!strcmp(what, "stream")) { /* a long-running CSV stream (live --log's writer) */
        struct hl_out o;
        if (hl_out_open(&o, path, &err) != 0) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        fputs("i,value\n", o.f);
        for (int i = 0; i < 400; ++i) {
            if (hl_out_mark(&o, &err) != 0) {
                fprintf(stderr, "%s; kept %llu complete records\n", err.msg, (unsigned long long)o.records);
                struct hl_error perr;
                if (hl_out_commit_prefix(&o, &perr) != 0)
                    fprintf(stderr, "%s\n", perr.msg);
                return 1;
            }
            fprintf(o.f, "%d,%.6f\n", i, i * 0.5);
        }
        if (hl_out_commit(&o, &err) != 0) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        return 0;
    }
    if (!strcmp(what, "trace")) {
        enum { N = 300 };
        double t[N];
        hl_quatd q[N];
        for (int i = 0; i < N; ++i)
            t[i] = i * 0.01, q[i] = hl_q_identity();
        struct rpl_trace tr;
        memset(&tr, 0, sizeof tr);
        tr.count = N, tr.time_s = t, tr.orientation = q;
        rc = rpl_trace_write_csv(&tr, path, &err);
    } else if (!strcmp(what, "png")) {
        enum { W = 64 };
        static uint8_t rgba[W * W * 4];
        for (size_t i = 0; i < sizeof rgba; ++i)
            rgba[i] = (uint8_t)(i * 2654435761u >> 13); /* noise: compresses poorly, so the PNG is large */
        rc = rnd_png_write(path, rgba, W, W, &err);
    } else {
        fprintf(stderr, "unknown child %s\n", what);
        return 2;
    }
    if (rc != 0)
        fprintf(stderr, "%s\n", err.msg);
    return rc ? 1 : 0;
}

static char self[4096];

/* The ASan runtime this program runs with, if any: it must come first in LD_PRELOAD. */
static void asan_runtime(char *out, size_t size)
{
    out[0] = '\0';
    FILE *m = fopen("/proc/self/maps", "r");
    char line[4096];
    while (m && fgets(line, sizeof line, m)) {
        char *p = strchr(line, '/');
        if (p && strstr(p, "libasan.so")) {
            p[strcspn(p, "\n")] = '\0';
            snprintf(out, size, "%s", p);
            break;
        }
    }
    if (m)
        fclose(m);
}

/* Runs the child with the shim: `budget` bytes allowed under dir; its exit code, stderr in errbuf. */
static int run_full(const char *shim, const char *what, const char *path, long budget, char *errbuf, size_t size)
{
    char errfile[600];
    snprintf(errfile, sizeof errfile, "%s/../child.err", dir);
    pid_t pid = fork();
    if (pid == 0) {
        char b[32];
        snprintf(b, sizeof b, "%ld", budget);
        setenv("HMDLOD_ENOSPC_DIR", dir, 1);
        setenv("HMDLOD_ENOSPC_AFTER", b, 1);
        char asan[4096], preload[8400];
        asan_runtime(asan, sizeof asan);
        snprintf(preload, sizeof preload, "%s%s%s", asan, asan[0] ? " " : "", shim);
        setenv("LD_PRELOAD", preload, 1);
        if (!freopen(errfile, "w", stderr) || !freopen("/dev/null", "w", stdout))
            _exit(3);
        execl(self, self, "child", what, path, (char *)NULL);
        _exit(4);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    size_t n = 0;
    char *e = tu_read_file(errfile, &n);
    snprintf(errbuf, size, "%s", e ? e : "");
    free(e);
    unlink(errfile);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

/* A failure that says which file and that the disk is full. */
static int names_full_disk(const char *msg, const char *name)
{
    return strstr(msg, name) && strstr(msg, "No space left on device");
}

static void test_disk_full(const char *shim)
{
    char msg[2048];
    /* Whole-file writers: for any budget they either write the whole file or leave the previous one
     * whole, with no temporary. The budgets: nothing, a few bytes (mid-header), mid-file, near the end. */
    static const char *const whole[] = {"trace", "png"};
    for (int w = 0; w < 2; ++w) {
        const char *name = w ? "full.png" : "full.csv";
        put(at(name), "previous\n");
        long full = -1; /* the complete file's size, measured with no limit */
        run_full(shim, whole[w], at("probe"), 1L << 40, msg, sizeof msg);
        struct stat st;
        if (stat(at("probe"), &st) == 0)
            full = (long)st.st_size;
        unlink(at("probe"));
        CHECK(full > 100);
        long budgets[] = {0, 7, full / 2, full - 3};
        for (int b = 0; b < 4; ++b) {
            int rc = run_full(shim, whole[w], at(name), budgets[b], msg, sizeof msg);
            int ok = rc == 1 && names_full_disk(msg, name) && same_text(at(name), "previous\n") &&
                     temporaries_in(dir) == 0;
            if (!ok)
                fprintf(stderr, "  %s, %ld bytes free: rc %d: %s", whole[w], budgets[b], rc, msg);
            CHECK(ok);
        }
        CHECK(run_full(shim, whole[w], at(name), full + 64, msg, sizeof msg) == 0 && !same_text(at(name), "previous\n"));
        unlink(at(name));
    }

    /* The long stream: its file ends on a whole row, and says so. */
    long stream_budgets[] = {0, 3, 9, 1000, 3000};
    for (int b = 0; b < 5; ++b) {
        unlink(at("stream.csv"));
        int rc = run_full(shim, "stream", at("stream.csv"), stream_budgets[b], msg, sizeof msg);
        CHECK(rc == 1 && names_full_disk(msg, "stream.csv") && strstr(msg, "complete records"));
        size_t n = 0;
        char *text = tu_read_file(at("stream.csv"), &n);
        if (stream_budgets[b] < 8) { /* not even the header: whatever the prefix holds is a header or nothing */
            CHECK(!text || n == 0 || (n == 8 && !memcmp(text, "i,value\n", 8)));
        } else {
            CHECK(text && n > 0 && (long)n <= stream_budgets[b] && text[n - 1] == '\n' && !memcmp(text, "i,value\n", 8));
        }
        long lines = 0, kept = -1; /* the header and every row are one record each */
        for (size_t i = 0; text && i < n; ++i)
            lines += text[i] == '\n';
        const char *k = strstr(msg, "kept ");
        if (k)
            kept = strtol(k + 5, NULL, 10);
        CHECK(kept == lines);
        free(text);
        CHECK(temporaries_in(dir) == 0);
    }

    /* The raw recording: readable to its last complete record, however little space there was. */
    const long rec_size = TRK_RECORDING_RECORD_OVERHEAD + REPORT;
    long rec_budgets[] = {0, 50, TRK_RECORDING_HEADER_SIZE, TRK_RECORDING_HEADER_SIZE + rec_size / 2,
                          TRK_RECORDING_HEADER_SIZE + 7 * rec_size + 5, TRK_RECORDING_HEADER_SIZE + RECORDS * rec_size - 1};
    for (int b = 0; b < 6; ++b) {
        long budget = rec_budgets[b];
        unlink(at("full.raw"));
        int rc = run_full(shim, "recording", at("full.raw"), budget, msg, sizeof msg);
        long whole_records = budget < TRK_RECORDING_HEADER_SIZE ? -1 : (budget - TRK_RECORDING_HEADER_SIZE) / rec_size;
        int ok = rc == 1 && names_full_disk(msg, "full.raw");
        if (whole_records < 0) {
            ok = ok && access(at("full.raw"), F_OK) != 0; /* no header, no recording */
        } else {
            struct hl_error err = {""};
            struct trk_recording_reader *r = trk_recording_open(at("full.raw"), &err);
            long got = 0;
            uint8_t buf[TRK_RECORDING_MAX_REPORT];
            int64_t t = 0;
            size_t len = 0;
            int step = 0;
            while (r && (step = trk_recording_next(r, &t, buf, sizeof buf, &len, &err)) == 1) {
                ok = ok && len == REPORT && buf[0] == (uint8_t)got && t == got * 1000;
                ++got;
            }
            ok = ok && r && step == 0 && !r->torn_tail && got == whole_records && strstr(msg, "incomplete");
            trk_recording_reader_close(r);
        }
        if (!ok)
            fprintf(stderr, "  recording, %ld bytes free: rc %d: %s", budget, rc, msg);
        CHECK(ok);
        CHECK(temporaries_in(dir) == 0);
    }
    unlink(at("full.raw"));
    unlink(at("stream.csv"));
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "child"))
        return child(argv[2], argv[3]);
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    self[n > 0 ? n : 0] = '\0';
    char top[128] = "/tmp/hmdlod-output-XXXXXX";
    if (!mkdtemp(top))
        return 1;
    snprintf(dir, sizeof dir, "%s/w", top); /* under a parent, so child.err sits outside the watched folder */
    mkdir(dir, 0700);

    test_out_basics();
    test_planted_links();
    const char *shim = getenv("HMDLOD_ENOSPC_SHIM");
    if (shim && access(shim, R_OK) == 0)
        test_disk_full(shim);
    else
        printf("skip: disk-full cases (HMDLOD_ENOSPC_SHIM names no library; ctest sets it)\n");

    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", top);
    if (system(cmd) != 0)
        fprintf(stderr, "note: could not remove %s\n", top);
    return tu_finish("output");
}
