/* The context every bench shares: output to stdout with a copy kept for --results, the machine,
 * commit and date a measurement was taken on, the shared data folder, and the RESULTS.md writer. */
#define _XOPEN_SOURCE 700 /* mkdtemp, nftw (POSIX 2008 with the XSI part) */
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench/bench.h"
#include "base/base.h"

extern char **environ;

/* ---- output: stdout, and a copy kept for --results ------------------------------------------ */

static FILE *bench_copy; /* memstream holding everything printed, or NULL */
static char *bench_copy_buf;
static size_t bench_copy_len;

void bch_emit(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    if (bench_copy) {
        va_start(ap, fmt);
        vfprintf(bench_copy, fmt, ap);
        va_end(ap);
    }
}

int bch_copy_begin(void)
{
    bench_copy = open_memstream(&bench_copy_buf, &bench_copy_len);
    return bench_copy ? 0 : -1;
}

int bch_copy_finish(const char *results, const char *heading, const char *who, int rc)
{
    if (!bench_copy)
        return rc;
    fclose(bench_copy);
    bench_copy = NULL;
    if (rc == 0 && bch_write_results_section(results, heading, bench_copy_buf) != 0)
        rc = 1;
    else if (rc == 0)
        fprintf(stderr, "%s: wrote section \"%s\" of %s\n", who, heading, results);
    free(bench_copy_buf);
    bench_copy_buf = NULL;
    bench_copy_len = 0;
    return rc;
}

/* ---- context: machine, commit, date ---------------------------------------------------------- */

static void cpu_model(char *out, size_t size)
{
    snprintf(out, size, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) != 0)
            continue;
        const char *v = strchr(line, ':');
        if (!v)
            break;
        v += 1 + strspn(v + 1, " \t");
        snprintf(out, size, "%.*s", (int)strcspn(v, "\n"), v);
        break;
    }
    fclose(f);
}

/* Directory of the running executable (for the commit and the shared folder); "" if unknown. */
static void exe_dir(char *out, size_t size)
{
    out[0] = '\0';
    char path[4096];
    ssize_t len = readlink("/proc/self/exe", path, sizeof path - 1);
    if (len <= 0)
        return;
    path[len] = '\0';
    char *slash = strrchr(path, '/');
    if (!slash)
        return;
    *slash = '\0';
    size_t dir_len = (size_t)(slash - path);
    if (dir_len + 1 <= size) /* a longer folder is treated as unknown, not cut */
        memcpy(out, path, dir_len + 1);
}

/* Runs git with fixed arguments (no shell, stderr discarded) in dir and reads the first line of its
 * stdout. Returns 1 and the line when git exited 0 and printed something; *any_output says whether
 * stdout was non-empty at all. */
static int run_git(const char *dir, const char *const *args, char *line, size_t size, int *any_output)
{
    int fds[2];
    if (pipe(fds) != 0)
        return 0;
    const char *argv[12] = {"git", "-C", dir};
    int argc = 3;
    for (; args[argc - 3] && argc < 11; ++argc)
        argv[argc] = args[argc - 3];
    argv[argc] = NULL;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&fa, fds[0]);
    posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    pid_t pid;
    int rc = posix_spawnp(&pid, "git", &fa, NULL, (char *const *)argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fds[1]);
    line[0] = '\0';
    size_t got = 0;
    if (rc == 0) {
        char buf[256];
        ssize_t r;
        int line_done = 0; /* keep the first line only, but drain the pipe so git never blocks */
        while ((r = read(fds[0], buf, sizeof buf)) > 0) {
            for (ssize_t i = 0; i < r && !line_done; ++i) {
                if (buf[i] == '\n' || got + 1 >= size)
                    line_done = 1;
                else
                    line[got++] = buf[i];
            }
            line[got] = '\0';
            if (any_output)
                *any_output = 1;
        }
    }
    close(fds[0]);
    int status = 0;
    if (rc != 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return 0;
    line[strcspn(line, "\n")] = '\0';
    return line[0] != '\0';
}

/* Short commit of the source tree: tried from the executable's folder (a build folder inside the
 * checkout), then the current directory; "unknown" when git or the repository is not there. */
static void commit_id(char *out, size_t size)
{
    char dirs[2][4096];
    exe_dir(dirs[0], sizeof dirs[0]);
    snprintf(dirs[1], sizeof dirs[1], ".");
    static const char *const rev[] = {"rev-parse", "--short", "HEAD", NULL};
    static const char *const dirty[] = {"status", "--porcelain", "--untracked-files=no", NULL};
    for (int i = 0; i < 2; ++i) {
        if (!dirs[i][0])
            continue;
        char line[128];
        if (run_git(dirs[i], rev, line, sizeof line, NULL)) {
            char ignored[128];
            int changed = 0;
            run_git(dirs[i], dirty, ignored, sizeof ignored, &changed);
            snprintf(out, size, "%s%s", line, changed ? " (with uncommitted changes)" : "");
            return;
        }
    }
    snprintf(out, size, "unknown");
}

char *bch_context_text(int argc, char **argv)
{
    char cpu[256], commit[192], date[64];
    cpu_model(cpu, sizeof cpu);
    commit_id(commit, sizeof commit);
    time_t now = time(NULL);
    struct tm tm_utc;
    gmtime_r(&now, &tm_utc);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", &tm_utc);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    if (!f)
        return NULL;
    fputs("- command: `hmdlod", f);
    for (int i = 0; i < argc; ++i)
        fprintf(f, " %s", argv[i]);
    fprintf(f, "`\n- machine: %s, %ld cores\n- commit: %s\n- date: %s\n", cpu, sysconf(_SC_NPROCESSORS_ONLN), commit,
            date);
    fclose(f);
    return text;
}

void bch_print_context(int argc, char **argv, const char *renderer)
{
    char *text = bch_context_text(argc, argv);
    bch_emit("%s", text ? text : "- context: out of memory\n");
    free(text);
    if (renderer)
        bch_emit("- renderer: %s\n", renderer);
}

/* ---- the shared folder ------------------------------------------------------------------------ */

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* HMDLOD_SHARED, else ../shared from the current directory, else from the executable's folder's
 * parent (a build folder inside the checkout next to shared/). 0 and the path, or −1. */
int bch_find_shared(char *out, size_t size)
{
    const char *env = getenv("HMDLOD_SHARED");
    if (env && env[0]) {
        snprintf(out, size, "%s", env);
        return is_dir(out) ? 0 : -1;
    }
    snprintf(out, size, "../shared");
    if (is_dir(out))
        return 0;
    char dir[2048]; /* half of out: room for the suffix */
    exe_dir(dir, sizeof dir);
    if (dir[0]) {
        snprintf(out, size, "%s/../../shared", dir);
        if (is_dir(out))
            return 0;
    }
    snprintf(out, size, "../shared");
    return -1;
}

/* Replaces (or appends) the section starting at `heading` in the Markdown file at path. */
int bch_write_results_section(const char *path, const char *heading, const char *body)
{
    char *old = NULL;
    size_t old_len = 0;
    struct hl_error rerr;
    if (hl_file_read_all(path, 0, &old, &old_len, &rerr) != 0) {
        if (errno != ENOENT) { /* a FIFO, device or unreadable file: never overwrite what was not read */
            fprintf(stderr, "hmdlod bench: %s\n", rerr.msg);
            return -1;
        }
        old = NULL, old_len = 0;
    }
    struct hl_out out;
    if (hl_out_open(&out, path, &rerr) != 0) {
        fprintf(stderr, "hmdlod bench: %s\n", rerr.msg);
        free(old);
        return -1;
    }
    FILE *o = out.f;
    const char *start = NULL;
    if (old) { /* the heading at the start of a line */
        for (const char *p = strstr(old, heading); p; p = strstr(p + 1, heading))
            if (p == old || p[-1] == '\n') {
                start = p;
                break;
            }
    }
    if (!old)
        fprintf(o, "# Results\n\nMeasured figures, each section with the command that produced it.\n\n");
    if (start) {
        fwrite(old, 1, (size_t)(start - old), o);
        const char *end = start + strlen(heading);
        const char *nl = strstr(end, "\n## "); /* the next section, kept */
        const char *next = nl ? nl + 1 : NULL;
        fputs(body, o);
        if (next)
            fprintf(o, "\n%s", next);
    } else {
        if (old) {
            fputs(old, o);
            if (old_len > 0 && old[old_len - 1] != '\n')
                fputc('\n', o);
            fputc('\n', o);
        }
        fputs(body, o);
    }
    free(old);
    if (hl_out_commit(&out, &rerr) != 0) {
        fprintf(stderr, "hmdlod bench: %s\n", rerr.msg);
        return -1;
    }
    return 0;
}

void bch_commit(char *out, size_t size) { commit_id(out, size); }

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    return remove(path);
}

int bch_temp_dir(const char *name, char *path, size_t size)
{
    if (snprintf(path, size, "/tmp/hmdlod-bench-%s-XXXXXX", name) >= (int)size || !mkdtemp(path)) {
        fprintf(stderr, "hmdlod bench %s: cannot create a temporary folder\n", name);
        return -1;
    }
    return 0;
}

void bch_temp_dir_remove(const char *path) { nftw(path, remove_entry, 8, FTW_DEPTH | FTW_PHYS); }
