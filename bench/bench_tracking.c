/* hmdlod bench tracking: every supported tracker's parser and fusion on the shared IMU streams,
 * accuracy against the ground truth and speed; OpenHMD's fusion measured on the same samples in the
 * same run where libopenhmd is built in (bench/bench_tracking_openhmd.c), and the OpenHMD / Monado
 * figures quoted by data/README.md beside them, labelled as quoted. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/bench_tracking_openhmd.h"
#include "tracking/tracking.h"


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
    bch_emit("%s tilt %.2f", who, rms);
    if (max > NA)
        bch_emit("/%.2f", max);
    if (yaw > NA)
        bch_emit(", yaw %+.1f °/min", yaw);
}

/* The "OpenHMD (measured)" row of a stream's table (columns as ours; no prediction, so the step and
 * abs columns hold only the hold figures; no reports to parse). res->samples = 0 when not measured.
 * 0, or −1 after saying why (an absent libopenhmd is not an error). */
static int bench_openhmd_row(const struct trk_imu_csv_row *rows, size_t n, int repeats,
                             struct bch_openhmd_result *res, const char *stream)
{
    struct trk_evaluate_options opt;
    trk_evaluate_options_default(&opt);
    struct hl_error err = {{0}};
    if (!bch_openhmd_available()) {
        memset(res, 0, sizeof *res);
        bch_emit("| OpenHMD: not measured (" BCH_OPENHMD_ABSENT ") | – | – | – | – | – | – | – | – | – | – |\n");
        return 0;
    }
    if (bch_openhmd_evaluate(rows, n, opt.yaw_skip_s, repeats, res, &err) != 0) {
        fprintf(stderr, "hmdlod bench tracking: %s: %s\n", stream, err.msg);
        bch_emit("| OpenHMD: not measured (failed: %s) | – | – | – | – | – | – | – | – | – | – |\n", err.msg);
        res->samples = 0;
        return -1;
    }
    const struct trk_evaluate_result *r = &res->acc;
    bch_emit("| OpenHMD %s (measured) ᶜ | %.0f | %.2f/%.2f | %+.2f | %.2f/%.2f | – | – (%.2f/%.2f/%.2f) | – (%.3f) "
               "| %.0f | %.2f/%.2f | %llu samples / – / – |\n",
               res->version, r->device_rate_hz, r->tilt_rms_deg, r->tilt_max_deg, r->yaw_drift_deg_per_min,
               r->yaw_rms_deg, r->yaw_max_deg, r->hold_step_rms_deg[0], r->hold_step_rms_deg[1],
               r->hold_step_rms_deg[2], r->hold_abs_rms_deg[1], res->fuse_ns_per_sample,
               res->sample_to_pose_us_median, res->sample_to_pose_us_p99, (unsigned long long)res->samples);
    fflush(stdout);
    return 0;
}

/* Where the OpenHMD row measured here and data/README.md's quoted OpenHMD figures differ. The quoted
 * ones are for the whole stream: a shorter run is not compared. */
static void print_measured_vs_quoted(const struct bench_stream *bs, const struct bch_openhmd_result *oh, int whole)
{
    const struct trk_evaluate_result *r = &oh->acc;
    if (!whole) {
        bch_emit("OpenHMD measured against quoted: not compared (this run covers %.1f s; the quoted figures are "
                   "for the full 60 s).\n", r->duration_s);
        return;
    }
    double d_rms = r->tilt_rms_deg - bs->openhmd_tilt_rms;
    int agree = fabs(d_rms) <= 0.1;
    bch_emit("OpenHMD measured against quoted: tilt RMS %.2f vs %.2f (%+.2f)", r->tilt_rms_deg, bs->openhmd_tilt_rms,
               d_rms);
    if (bs->openhmd_tilt_max > NA) {
        double d = r->tilt_max_deg - bs->openhmd_tilt_max;
        agree = agree && fabs(d) <= 0.2;
        bch_emit(", max %.2f vs %.2f (%+.2f)", r->tilt_max_deg, bs->openhmd_tilt_max, d);
    }
    if (bs->openhmd_yaw > NA) {
        double d = r->yaw_drift_deg_per_min - bs->openhmd_yaw;
        agree = agree && fabs(d) <= 0.5;
        bch_emit(", yaw %+.1f vs %+.1f °/min (%+.1f)", r->yaw_drift_deg_per_min, bs->openhmd_yaw, d);
    }
    bch_emit(": %s.\n", agree ? "they agree (tilt within 0.1° RMS / 0.2° max, yaw within 0.5 °/min)"
                                 : "they DIFFER beyond 0.1° RMS / 0.2° max / 0.5 °/min");
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
    bch_emit("\n### %s (%.1f s)\n\n", bs->name, (double)(use - 1) * 0.001);
    bch_emit("| device | samples/s | tilt RMS/max ° | yaw °/min (no mag) | yaw RMS/max ° after 5 s (no mag) "
         "| yaw RMS/max ° calibrated "
         "| step 10/20/40 ms ° (hold) | abs 20 ms ° (hold) "
         "| parse+fuse ns/sample | report→pose µs p50/p99 | reports / lost / clipped |\n");
    bch_emit("|---|---|---|---|---|---|---|---|---|---|---|\n");
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
        char yaw[64], yawrms[64], yawcal[64] = "–";
        if (r.has_mag) {
            snprintf(yaw, sizeof yaw, "%+.2f (%+.2f)", r.yaw_drift_deg_per_min, r.nomag_yaw_drift_deg_per_min);
            snprintf(yawrms, sizeof yawrms, "%.2f/%.2f (%.2f/%.2f)", r.yaw_rms_deg, r.yaw_max_deg, r.nomag_yaw_rms_deg,
                     r.nomag_yaw_max_deg);
            snprintf(yawcal, sizeof yawcal, "%.2f/%.2f", r.cal_yaw_rms_deg, r.cal_yaw_max_deg);
        } else {
            snprintf(yaw, sizeof yaw, "%+.2f", r.yaw_drift_deg_per_min);
            snprintf(yawrms, sizeof yawrms, "%.2f/%.2f", r.yaw_rms_deg, r.yaw_max_deg);
        }
        bch_emit("| %s%s | %.0f | %.2f/%.2f | %s | %s | %s | %.3f/%.3f/%.3f (%.2f/%.2f/%.2f) | %.3f (%.3f) | %.0f | %.2f/%.2f "
             "| %llu / %llu / %llu |\n",
             trk_evaluate_device_name(r.kind), r.has_mag ? " ᵇ" : r.kind == TRK_DEVICE_HDK ? " ᵃ" : "",
             r.device_rate_hz, r.tilt_rms_deg, r.tilt_max_deg, yaw, yawrms, yawcal, r.step_rms_deg[0], r.step_rms_deg[1],
             r.step_rms_deg[2], r.hold_step_rms_deg[0], r.hold_step_rms_deg[1], r.hold_step_rms_deg[2],
             r.abs_rms_deg[1], r.hold_abs_rms_deg[1], r.parse_fuse_ns_per_sample, r.report_to_pose_us_median,
             r.report_to_pose_us_p99, (unsigned long long)r.reports_fed, (unsigned long long)r.lost,
             (unsigned long long)r.gyro_clipped);
        fflush(stdout);
    }
    struct bch_openhmd_result oh;
    if (bench_openhmd_row(rows, use, repeats, &oh, bs->name) != 0)
        rc = -1;
    bch_emit("\nQuoted, not measured here (data/README.md §5, full 60 s, warm start): ");
    print_beat("OpenHMD fusion.c", bs->openhmd_tilt_rms, bs->openhmd_tilt_max, bs->openhmd_yaw);
    bch_emit("; ");
    print_beat("Monado m_imu_3dof", bs->monado_tilt_rms, bs->monado_tilt_max, bs->monado_yaw);
    bch_emit(".\n");
    if (oh.samples > 0)
        print_measured_vs_quoted(bs, &oh, use == n);
    trk_imu_csv_free(rows);
    return rc;
}

static void print_tracking_notes(void)
{
    bch_emit("\nHow measured (tracking/evaluate.c): each stream's 1 kHz body-frame samples are encoded into the "
         "device's own reports at its native rate (PSVR: 2 kHz by linear interpolation, 2 samples a report; "
         "OSVR HDK: 400 Hz), parsed and fused by hmdlod, warm start (truth at t = 0, 0.1° prior). "
         "tilt = angle between true and estimated gravity; yaw = least-squares slope of the heading error; "
         "step = body-frame error of the predicted step over the horizon (constant ω), hold = no prediction; "
         "abs = angle to the true future orientation (includes the unobservable heading drift). "
         "parse+fuse = whole stream fed without clock reads, per sample fused, median of the repeats; "
         "report→pose = per report, from having its bytes to a 20 ms predicted pose (one clock read included). "
         "clipped = samples beyond the device's gyro range (Vive default ±500 °/s).\n"
         "ᵃ The HDK fuses on chip: its tilt and yaw come from an assumed on-chip error model (0.1° per axis "
         "Gauss–Markov, τ 1 s, 0.5 °/min yaw drift), not from hmdlod's fusion; its prediction columns are real.\n"
         "ᵇ Rift: the streams have no magnetometer, so one is synthesized from the true orientation (an assumption, "
         "not a measurement): world field 0.48 gauss, 60° dip; reading = R(q)ᵀB + a hard-iron offset (each axis "
         "uniform ±0.25 gauss, drawn from the seed, estimated online by the fusion's gyro-aided fit) + 2 mgauss white "
         "noise per axis (HMC5983 class), quantized to 1e-4 gauss, one per report. Figures in parentheses: the "
         "same reports with the fusion ignoring the magnetometer (yaw unobservable). yaw RMS/max: heading error "
         "after the first 5 s (warm start at the true heading); before the fit is in use (10–15 s into "
         "motion) heading drifts as without. calibrated: the fusion given the true offset instead (as after "
         "LibOVR's calibration step). Other devices have no magnetometer.\n"
         "ᶜ OpenHMD: Debian's libopenhmd, its own fusion (ofusion_update) through its external-sensor device, fed "
         "the stream's 1 kHz samples straight (no reports; its frame is the streams': body +X right, +Y up, +Z "
         "back, world +Y up, accel +g up at rest — checked by tests/test_tracking_openhmd.c), warm started by one "
         "sample that turns it from identity to the truth at t = 0, scored by the same code as ours "
         "(tracking/accuracy.c). It has no magnetometer use, no bias estimation and no prediction: its step and abs "
         "columns are the hold figures. fuse ns/sample = setf + ctx_update per sample over the whole stream; "
         "the µs column = per sample, setf → getf.\n");
}


void bch_tracking_print_streams(FILE *f)
{
    for (size_t i = 0; i < N_BENCH_STREAMS; ++i)
        fprintf(f, " %s", bench_streams[i].name);
}

int bch_tracking(const struct bch_tracking_options *o, int full_argc, char **full_argv)
{
    const char *stream = o->stream ? o->stream : "all", *results = o->results;
    double seconds = o->seconds;
    long repeats = o->repeats;
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
    if (bch_find_shared(shared, sizeof shared) != 0) {
        fprintf(stderr, "hmdlod bench tracking: skip: the shared data folder is absent (%s); set HMDLOD_SHARED\n",
                shared);
        return 0;
    }
    if (results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench tracking: out of memory\n");
        return 1;
    }
    bch_emit(BCH_TRACKING_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, NULL);
    int rc = 0;
    for (size_t s = first; s < last; ++s)
        if (bench_one_stream(shared, &bench_streams[s], seconds, (int)repeats) != 0)
            rc = 1;
    print_tracking_notes();
    return bch_copy_finish(results, BCH_TRACKING_HEADING, "hmdlod bench tracking", rc);
}
