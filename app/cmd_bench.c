/* hmdlod bench: reproducible measurements with their context (machine, commit, command line, date),
 * printed as Markdown so a run can go straight into docs/RESULTS.md (--results does that).
 * Sub-benches live in the table below; only `tracking` exists so far (lodgen / optimizer to come). */
#define _POSIX_C_SOURCE 200809L
#include <fcntl.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "app/commands.h"
#include "tracking/tracking.h"

extern char **environ;

/* ---- output: stdout, and a copy kept for --results ------------------------------------------ */

static FILE *bench_copy; /* memstream holding everything printed, or NULL */

static void emit(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;
static void emit(const char *fmt, ...)
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

static void print_context(int argc, char **argv)
{
    char cpu[256], commit[192], date[64];
    cpu_model(cpu, sizeof cpu);
    commit_id(commit, sizeof commit);
    time_t now = time(NULL);
    struct tm tm_utc;
    gmtime_r(&now, &tm_utc);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", &tm_utc);
    emit("- command: `hmdlod");
    for (int i = 0; i < argc; ++i)
        emit(" %s", argv[i]);
    emit("`\n- machine: %s, %ld cores\n- commit: %s\n- date: %s\n", cpu, sysconf(_SC_NPROCESSORS_ONLN), commit,
         date);
}

/* ---- the shared folder ------------------------------------------------------------------------ */

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* HMDLOD_SHARED, else ../shared from the current directory, else from the executable's folder's
 * parent (a build folder inside the checkout next to shared/). 0 and the path, or −1. */
static int find_shared(char *out, size_t size)
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

/* ---- bench tracking --------------------------------------------------------------------------- */

/* The shared streams and data/README.md §5's "figures to beat" (full 60 s, warm start). */
struct bench_stream {
    const char *name;
    double openhmd_tilt_rms, openhmd_tilt_max, openhmd_yaw; /* max, yaw < -1e9: not given */
    double monado_tilt_rms, monado_tilt_max, monado_yaw;
};
#define NA (-1e10)
static const struct bench_stream bench_streams[] = {
    {"corbillon_user1_t30", 1.81, 3.32, 28.7, 1.32, 2.48, 29.0},
    {"corbillon_user2_t60", 1.92, 3.06, -9.4, 1.47, 2.85, -9.4},
    {"nasrabadi_322SAJ_9_t0", 2.82, 4.05, -11.0, 2.54, 4.00, -11.1},
    {"still_desk_tilt10", 2.55, NA, NA, 2.37, NA, NA},
};
#define N_BENCH_STREAMS (sizeof bench_streams / sizeof bench_streams[0])

static const enum trk_device_kind bench_kinds[] = {TRK_DEVICE_RIFT_DK1, TRK_DEVICE_RIFT_DK2, TRK_DEVICE_RIFT_CV1,
                                                   TRK_DEVICE_PSVR,     TRK_DEVICE_VIVE,     TRK_DEVICE_VIVE_PRO_INDEX,
                                                   TRK_DEVICE_HDK};

static void print_beat(const char *who, double rms, double max, double yaw)
{
    emit("%s tilt %.2f", who, rms);
    if (max > NA)
        emit("/%.2f", max);
    if (yaw > NA)
        emit(", yaw %+.1f °/min", yaw);
}

static int bench_one_stream(const char *shared, const struct bench_stream *bs, double seconds, int repeats)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/data/imu/%s.csv", shared, bs->name);
    struct trk_imu_csv_row *rows = NULL;
    size_t n = 0;
    struct hl_error err = {{0}};
    if (trk_imu_csv_read(path, &rows, &n, &err) != 0) {
        fprintf(stderr, "hmdlod bench tracking: %s\n", err.msg);
        return -1;
    }
    size_t use = n;
    if (seconds > 0 && (size_t)(seconds * 1000.0) + 1 < n)
        use = (size_t)(seconds * 1000.0) + 1;
    emit("\n### %s (%.1f s)\n\n", bs->name, (double)(use - 1) * 0.001);
    emit("| device | samples/s | tilt RMS/max ° | yaw °/min | step 10/20/40 ms ° (hold) | abs 20 ms ° (hold) "
         "| parse+fuse ns/sample | report→pose µs p50/p99 | reports / lost / clipped |\n");
    emit("|---|---|---|---|---|---|---|---|---|\n");
    int rc = 0;
    for (size_t i = 0; i < sizeof bench_kinds / sizeof bench_kinds[0]; ++i) {
        struct trk_evaluate_options opt;
        trk_evaluate_options_default(&opt);
        opt.timing_repeats = repeats;
        struct trk_evaluate_result r;
        if (trk_evaluate_device(bench_kinds[i], rows, use, &opt, &r, &err) != 0) {
            fprintf(stderr, "hmdlod bench tracking: %s: %s\n", bs->name, err.msg);
            rc = -1;
            continue;
        }
        emit("| %s%s | %.0f | %.2f/%.2f | %+.2f | %.3f/%.3f/%.3f (%.2f/%.2f/%.2f) | %.3f (%.3f) | %.0f | %.2f/%.2f "
             "| %llu / %llu / %llu |\n",
             trk_evaluate_device_name(r.kind), r.kind == TRK_DEVICE_HDK ? " ᵃ" : "", r.device_rate_hz,
             r.tilt_rms_deg, r.tilt_max_deg, r.yaw_drift_deg_per_min, r.step_rms_deg[0], r.step_rms_deg[1],
             r.step_rms_deg[2], r.hold_step_rms_deg[0], r.hold_step_rms_deg[1], r.hold_step_rms_deg[2],
             r.abs_rms_deg[1], r.hold_abs_rms_deg[1], r.parse_fuse_ns_per_sample, r.report_to_pose_us_median,
             r.report_to_pose_us_p99, (unsigned long long)r.reports_fed, (unsigned long long)r.lost,
             (unsigned long long)r.gyro_clipped);
        fflush(stdout);
    }
    emit("\nFigures to beat (data/README.md §5, full 60 s, warm start): ");
    print_beat("OpenHMD fusion.c", bs->openhmd_tilt_rms, bs->openhmd_tilt_max, bs->openhmd_yaw);
    emit("; ");
    print_beat("Monado m_imu_3dof", bs->monado_tilt_rms, bs->monado_tilt_max, bs->monado_yaw);
    emit(".\n");
    trk_imu_csv_free(rows);
    return rc;
}

static void print_tracking_notes(void)
{
    emit("\nHow measured (tracking/evaluate.c): each stream's 1 kHz body-frame samples are encoded into the "
         "device's own reports at its native rate (PSVR: 2 kHz by linear interpolation, 2 samples a report; "
         "OSVR HDK: 400 Hz), parsed and fused by hmdlod, warm start (truth at t = 0, 0.1° prior). "
         "tilt = angle between true and estimated gravity; yaw = least-squares slope of the heading error; "
         "step = body-frame error of the predicted step over the horizon (constant ω), hold = no prediction; "
         "abs = angle to the true future orientation (includes the unobservable heading drift). "
         "parse+fuse = whole stream fed without clock reads, per sample fused, median of the repeats; "
         "report→pose = per report, from having its bytes to a 20 ms predicted pose (one clock read included). "
         "clipped = samples beyond the device's gyro range (Vive default ±500 °/s).\n"
         "ᵃ The HDK fuses on chip: its tilt and yaw come from an assumed on-chip error model (0.1° per axis "
         "Gauss–Markov, τ 1 s, 0.5 °/min yaw drift), not from hmdlod's fusion; its prediction columns are real.\n");
}

/* Replaces (or appends) the section starting at `heading` in the Markdown file at path. */
static int write_results_section(const char *path, const char *heading, const char *body)
{
    char *old = NULL;
    size_t old_len = 0;
    FILE *f = fopen(path, "rb");
    if (f) {
        if (fseek(f, 0, SEEK_END) == 0) {
            long len = ftell(f);
            if (len >= 0 && fseek(f, 0, SEEK_SET) == 0 && (old = malloc((size_t)len + 1))) {
                old_len = fread(old, 1, (size_t)len, f);
                old[old_len] = '\0';
            }
        }
        fclose(f);
    }
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *o = fopen(tmp, "wb");
    if (!o) {
        fprintf(stderr, "hmdlod bench: cannot write %s\n", tmp);
        free(old);
        return -1;
    }
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
    if (fclose(o) != 0 || rename(tmp, path) != 0) {
        fprintf(stderr, "hmdlod bench: cannot write %s\n", path);
        remove(tmp);
        return -1;
    }
    return 0;
}

#define TRACKING_HEADING "## Trackers (hmdlod bench tracking)"

static int bench_tracking(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        printf("usage: hmdlod bench tracking [--stream NAME|all] [--seconds S] [--repeats N] [--results FILE]\n\n"
               "Encodes each shared IMU stream (shared/data/imu) into every supported tracker's reports at its\n"
               "native rate, parses and fuses them, and prints accuracy against the ground truth and speed,\n"
               "beside the OpenHMD / Monado figures from data/README.md. Markdown output.\n"
               "  --stream NAME   one of the streams below, or all (default)\n"
               "  --seconds S     only the first S seconds of each stream (default: all 60)\n"
               "  --repeats N     whole-stream timing passes, median reported (default 5)\n"
               "  --results FILE  also write the output as the section \"" TRACKING_HEADING "\" of FILE\n"
               "                  (e.g. docs/RESULTS.md; other sections are kept)\n"
               "streams:");
        for (size_t i = 0; i < N_BENCH_STREAMS; ++i)
            printf(" %s", bench_streams[i].name);
        printf("\nThe shared folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.\n");
        return 0;
    }
    const char *stream = "all", *results = NULL;
    double seconds = 0;
    long repeats = 5;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--stream") && i + 1 < argc) {
            stream = argv[++i];
        } else if (!strcmp(argv[i], "--seconds")) {
            if (app_parse_double("--seconds", i + 1 < argc ? argv[++i] : NULL, &seconds) != 0)
                return 1;
            if (!(seconds >= 0.5 && seconds <= 1e6)) {
                fprintf(stderr, "hmdlod bench tracking: --seconds %g: need at least 0.5\n", seconds);
                return 1;
            }
        } else if (!strcmp(argv[i], "--repeats")) {
            if (app_parse_long("--repeats", i + 1 < argc ? argv[++i] : NULL, 1, 1000, &repeats) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--results") && i + 1 < argc) {
            results = argv[++i];
        } else {
            fprintf(stderr, "hmdlod bench tracking: unknown or incomplete option '%s' (try --help)\n", argv[i]);
            return 1;
        }
    }
    size_t first = 0, last = N_BENCH_STREAMS;
    if (strcmp(stream, "all") != 0) {
        size_t len = strlen(stream);
        if (len > 4 && !strcmp(stream + len - 4, ".csv"))
            len -= 4;
        for (first = 0; first < N_BENCH_STREAMS; ++first)
            if (strlen(bench_streams[first].name) == len && !strncmp(bench_streams[first].name, stream, len))
                break;
        if (first == N_BENCH_STREAMS) {
            fprintf(stderr, "hmdlod bench tracking: unknown stream '%s'; known:", stream);
            for (size_t i = 0; i < N_BENCH_STREAMS; ++i)
                fprintf(stderr, " %s", bench_streams[i].name);
            fprintf(stderr, " all\n");
            return 1;
        }
        last = first + 1;
    }
    char shared[4096];
    if (find_shared(shared, sizeof shared) != 0) {
        fprintf(stderr, "hmdlod bench tracking: skip: the shared data folder is absent (%s); set HMDLOD_SHARED\n",
                shared);
        return 0;
    }
    char *copy_buf = NULL;
    size_t copy_len = 0;
    if (results && !(bench_copy = open_memstream(&copy_buf, &copy_len))) {
        fprintf(stderr, "hmdlod bench tracking: out of memory\n");
        return 1;
    }
    emit(TRACKING_HEADING "\n\n");
    print_context(full_argc, full_argv);
    int rc = 0;
    for (size_t s = first; s < last; ++s)
        if (bench_one_stream(shared, &bench_streams[s], seconds, (int)repeats) != 0)
            rc = 1;
    print_tracking_notes();
    if (bench_copy) {
        fclose(bench_copy);
        bench_copy = NULL;
        if (rc == 0 && write_results_section(results, TRACKING_HEADING, copy_buf) != 0)
            rc = 1;
        else if (rc == 0)
            fprintf(stderr, "hmdlod bench tracking: wrote section \"%s\" of %s\n", TRACKING_HEADING, results);
        free(copy_buf);
    }
    return rc;
}

/* ---- dispatch --------------------------------------------------------------------------------- */

struct bench {
    const char *name;
    int (*run)(int argc, char **argv, int full_argc, char **full_argv);
    const char *summary;
};
static const struct bench benches[] = {
    {"tracking", bench_tracking, "tracker accuracy and parse+fuse speed on the shared IMU streams, per device"},
};
#define N_BENCHES (sizeof benches / sizeof benches[0])

static void print_bench_usage(FILE *f)
{
    fprintf(f, "usage: hmdlod bench <name> [options]   (hmdlod bench <name> --help)\n\nbenches:\n");
    for (size_t i = 0; i < N_BENCHES; ++i)
        fprintf(f, "  %-9s %s\n", benches[i].name, benches[i].summary);
}

int cmd_bench(int argc, char **argv)
{
    if (argc < 2) {
        print_bench_usage(stderr);
        return 1;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        print_bench_usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < N_BENCHES; ++i)
        if (!strcmp(argv[1], benches[i].name))
            return benches[i].run(argc - 1, argv + 1, argc, argv);
    fprintf(stderr, "hmdlod bench: unknown bench '%s'; known:", argv[1]);
    for (size_t i = 0; i < N_BENCHES; ++i)
        fprintf(stderr, " %s", benches[i].name);
    fprintf(stderr, "\n");
    return 1;
}
