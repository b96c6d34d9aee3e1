/* tracking/ end to end: shared IMU stream → each device's reports at its native rate → parser →
 * fusion → ground truth (tracking/evaluate.c). Goals from data/README.md §5 and the issue: tilt RMS
 * ≤ 1° (warm start) and constant-ω prediction at 20 ms beating the hold baseline ≥ 5× in step error,
 * with sane counters; also with reports lost on the bus and with a device counter wrapping mid-stream.
 * The OSVR HDK fuses on chip, so its tilt is set by the error model evaluate.c assumes (0.1° per
 * axis), not by hmdlod's fusion: its check guards the report path (Q1.14 quaternion, axes), not a
 * filter. Runtime: 30 s slices of two streams keep this under a few seconds plain, well under a
 * minute with ASan + UBSan. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tests/test_util.h"
#include "tracking/tracking.h"

static const enum trk_device_kind kinds[] = {TRK_DEVICE_RIFT_DK1, TRK_DEVICE_RIFT_DK2, TRK_DEVICE_RIFT_CV1,
                                             TRK_DEVICE_PSVR,     TRK_DEVICE_VIVE,     TRK_DEVICE_VIVE_PRO_INDEX,
                                             TRK_DEVICE_HDK};
#define NKINDS (sizeof kinds / sizeof kinds[0])
#define SLICE_ROWS 30000 /* 30 s of the 1 kHz stream */

static void print_result(const char *label, const struct trk_evaluate_result *r)
{
    printf("  %-15s %-10s tilt %.3f/%.3f deg  yaw %+6.2f deg/min  step 10/20/40 ms %.3f/%.3f/%.3f (hold "
           "%.2f/%.2f/%.2f)  abs20 %.3f (hold %.3f)  reports %llu (dropped %llu) lost %llu dup %llu  "
           "%.0f ns/sample  %.2f/%.2f us\n",
           trk_evaluate_device_name(r->kind), label, r->tilt_rms_deg, r->tilt_max_deg, r->yaw_drift_deg_per_min,
           r->step_rms_deg[0], r->step_rms_deg[1], r->step_rms_deg[2], r->hold_step_rms_deg[0],
           r->hold_step_rms_deg[1], r->hold_step_rms_deg[2], r->abs_rms_deg[1], r->hold_abs_rms_deg[1],
           (unsigned long long)r->reports_fed, (unsigned long long)r->reports_dropped,
           (unsigned long long)r->lost, (unsigned long long)r->duplicates, r->parse_fuse_ns_per_sample,
           r->report_to_pose_us_median, r->report_to_pose_us_p99);
}

/* The goal checks shared by every run. */
static void check_goal(const struct trk_evaluate_result *r)
{
    CHECK(r->tilt_rms_deg <= 1.0);
    CHECK(r->step_rms_deg[1] * 5.0 <= r->hold_step_rms_deg[1]);
    CHECK(r->abs_rms_deg[1] < r->hold_abs_rms_deg[1]);
    CHECK(r->reports_rejected == 0);
    CHECK(r->backward == 0);
    /* The Vive's default gyro range is ±500 deg/s (DEVICES.md §2a); the 322SAJ_9 turn peaks at
     * 612 deg/s, so a few samples clip there — as on the device. The others' ranges are wider. */
    if (r->kind == TRK_DEVICE_VIVE || r->kind == TRK_DEVICE_VIVE_PRO_INDEX)
        CHECK(r->gyro_clipped * 100 < r->device_samples);
    else
        CHECK(r->gyro_clipped == 0);
    CHECK(isfinite(r->yaw_drift_deg_per_min));
}

static void check_native(const struct trk_evaluate_result *r, size_t rows)
{
    check_goal(r);
    CHECK(r->reports_dropped == 0);
    CHECK(r->lost == 0);
    /* The Vive ring repeats the two previous samples in every report: skipped as duplicates. */
    if (r->kind == TRK_DEVICE_VIVE || r->kind == TRK_DEVICE_VIVE_PRO_INDEX)
        CHECK(r->duplicates == 2 * r->reports_fed);
    else
        CHECK(r->duplicates == 0);
    CHECK(r->reports_fed == r->reports_built);
    CHECK(r->evaluated == r->reports_fed);
    CHECK(r->samples_fused == r->samples_parsed);
    /* Native rates: PSVR 2 samples per stream ms (from row 1), HDK 400 Hz, others 1 per row. */
    if (r->kind == TRK_DEVICE_PSVR)
        CHECK(r->device_samples == 2 * (rows - 1));
    else if (r->kind == TRK_DEVICE_HDK)
        CHECK(r->device_samples == (uint64_t)((rows - 1) * 2 / 5 + 1));
    else
        CHECK(r->device_samples == rows);
    CHECK(r->samples_parsed == r->device_samples);
    CHECK_NEAR(r->device_rate_hz, r->kind == TRK_DEVICE_PSVR ? 2000.0 : r->kind == TRK_DEVICE_HDK ? 400.0 : 1000.0,
               r->kind == TRK_DEVICE_PSVR ? 2.0 : 1.0);
    CHECK(r->parse_fuse_ns_per_sample >= 0);
    CHECK(r->report_to_pose_us_median > 0 && r->report_to_pose_us_p99 >= r->report_to_pose_us_median);
    if (r->kind == TRK_DEVICE_HDK) /* by construction: drift 0.5 deg/min in the error model */
        CHECK_NEAR(r->yaw_drift_deg_per_min, 0.5, 0.3);
}

static int load(const char *file, struct trk_imu_csv_row **rows, size_t *n)
{
    const char *path = tu_shared_path(file);
    if (!path)
        return -1;
    struct hl_error err = {{0}};
    if (trk_imu_csv_read(path, rows, n, &err) != 0) {
        fprintf(stderr, "%s\n", err.msg);
        CHECK(0);
        return -1;
    }
    CHECK(*n >= SLICE_ROWS);
    return *n >= SLICE_ROWS ? 0 : -1;
}

static void test_native(const char *file, size_t first_row)
{
    struct trk_imu_csv_row *rows = NULL;
    size_t n = 0;
    if (load(file, &rows, &n) != 0)
        return;
    printf("%s rows %zu..%zu, native rates\n", strrchr(file, '/') + 1, first_row, first_row + SLICE_ROWS - 1);
    struct trk_evaluate_options opt;
    trk_evaluate_options_default(&opt);
    opt.timing_repeats = 1;
    for (size_t i = 0; i < NKINDS; ++i) {
        struct trk_evaluate_result r;
        struct hl_error err = {{0}};
        int rc = trk_evaluate_device(kinds[i], rows + first_row, SLICE_ROWS, &opt, &r, &err);
        CHECK(rc == 0);
        if (rc != 0) {
            fprintf(stderr, "%s\n", err.msg);
            continue;
        }
        print_result("native", &r);
        check_native(&r, SLICE_ROWS);
        CHECK(r.parse_fuse_ns_per_sample > 0);
    }
    trk_imu_csv_free(rows);
}

/* Lost reports (every 97th withheld) and a counter wrap 10 s into the slice, on every device. */
static void test_drops_and_wrap(const char *file)
{
    struct trk_imu_csv_row *rows = NULL;
    size_t n = 0;
    if (load(file, &rows, &n) != 0)
        return;
    printf("%s rows 0..%d, dropped reports / counter wrap\n", strrchr(file, '/') + 1, SLICE_ROWS - 1);
    for (size_t i = 0; i < NKINDS; ++i) {
        struct trk_evaluate_options opt;
        trk_evaluate_options_default(&opt);
        opt.timing_repeats = 0;
        opt.drop_report_every = 97;
        struct trk_evaluate_result r;
        struct hl_error err = {{0}};
        CHECK(trk_evaluate_device(kinds[i], rows, SLICE_ROWS, &opt, &r, &err) == 0);
        print_result("drop 1/97", &r);
        check_goal(&r);
        CHECK(r.reports_dropped == r.reports_built / 97);
        CHECK(r.reports_fed == r.reports_built - r.reports_dropped);
        /* What the parser can see of a lost report: the Vive ring repeats the last three samples, so
         * one lost report loses nothing; the HDK's sequence byte shows each gap; a Rift (N = 1) or
         * PSVR report carries no sequence the parser checks, so the gap is only a longer dt. */
        if (kinds[i] == TRK_DEVICE_HDK)
            CHECK(r.lost == r.reports_dropped);
        else
            CHECK(r.lost == 0);
        if (kinds[i] == TRK_DEVICE_VIVE || kinds[i] == TRK_DEVICE_VIVE_PRO_INDEX)
            CHECK(r.samples_parsed == r.device_samples);

        trk_evaluate_options_default(&opt);
        opt.timing_repeats = 0;
        opt.counter_wrap_at_s = 10.0;
        CHECK(trk_evaluate_device(kinds[i], rows, SLICE_ROWS, &opt, &r, &err) == 0);
        print_result("wrap@10s", &r);
        check_native(&r, SLICE_ROWS);
    }
    trk_imu_csv_free(rows);
}

static void test_bad_input(void)
{
    struct trk_imu_csv_row rows[200];
    memset(rows, 0, sizeof rows);
    for (int i = 0; i < 200; ++i) {
        rows[i].t_s = i * 0.002; /* 500 Hz: not a shared stream */
        rows[i].truth = hl_q_identity();
        rows[i].accel_mps2 = hl_v3(0, 9.80665, 0);
    }
    struct trk_evaluate_result r;
    struct hl_error err = {{0}};
    CHECK(trk_evaluate_device(TRK_DEVICE_RIFT_DK2, rows, 200, NULL, &r, &err) == -1);
    CHECK(strstr(err.msg, "1 kHz") != NULL);
    CHECK(trk_evaluate_device(TRK_DEVICE_RIFT_DK2, rows, 10, NULL, &r, &err) == -1);
    /* A still, upright, noise-free head: every device tracks it to within its quantization. */
    for (int i = 0; i < 200; ++i)
        rows[i].t_s = i * 0.001;
    for (size_t i = 0; i < NKINDS; ++i) {
        struct trk_evaluate_options opt;
        trk_evaluate_options_default(&opt);
        opt.hdk_yaw_drift_deg_per_min = 0;
        opt.hdk_error_sigma_deg = 0;
        opt.hdk_gyro_noise_degps_rthz = 0;
        CHECK(trk_evaluate_device(kinds[i], rows, 200, &opt, &r, &err) == 0);
        CHECK(r.tilt_rms_deg < 0.05);
        CHECK(r.step_rms_deg[1] < 0.01);
    }
    CHECK(strcmp(trk_evaluate_device_name(TRK_DEVICE_HDK), "OSVR HDK") == 0);
}

/* Rift DK2 with the synthesized magnetometer (evaluate.c: 0.48 gauss, 60 deg dip, 2 mgauss noise,
 * hard iron ±0.25 gauss per axis) on 30 s of corbillon_user1_t30. Calibrated offset: heading held to
 * the start heading — measured RMS 0.29 deg, max 0.51 deg after 5 s, slope −0.7 deg/min, against
 * 2.1/4.1 deg and −6.9 deg/min without. The least-squares slope of a bounded error over 30 s is not
 * a drift (a ±0.5 deg wander moves it by ~1 deg/min), so it is bounded at 1.5 deg/min and the RMS/max
 * carry the claim, with margin for other seeds (0.1–0.3 deg RMS measured on the three motion streams).
 * With the offset fitted online (gyro-aided, fusion.c) it is found to < 0.01 gauss here, but only
 * ~10 s in: the drift before that dominates (measured RMS 1.75 vs 2.1 deg), so only sanity is checked. */
static void test_magnetometer(void)
{
    struct trk_imu_csv_row *rows = NULL;
    size_t n = 0;
    if (load("data/imu/corbillon_user1_t30.csv", &rows, &n) != 0)
        return;
    struct trk_evaluate_options opt;
    trk_evaluate_options_default(&opt);
    opt.timing_repeats = 0;
    opt.mag_hard_iron_known = 1;
    struct trk_evaluate_result r;
    struct hl_error err = {{0}};
    CHECK(trk_evaluate_device(TRK_DEVICE_RIFT_DK2, rows, SLICE_ROWS, &opt, &r, &err) == 0);
    printf("Rift DK2 + magnetometer (calibrated): tilt %.3f (%.3f) yaw %+.2f (%+.2f) deg/min, RMS/max %.2f/%.2f "
           "(%.2f/%.2f) deg, updates %llu, gated %llu\n", r.tilt_rms_deg, r.nomag_tilt_rms_deg, r.yaw_drift_deg_per_min,
           r.nomag_yaw_drift_deg_per_min, r.yaw_rms_deg, r.yaw_max_deg, r.nomag_yaw_rms_deg, r.nomag_yaw_max_deg,
           (unsigned long long)r.mag_updates, (unsigned long long)r.mag_gated);
    CHECK(r.has_mag);
    CHECK(r.tilt_rms_deg <= 1.0 && r.nomag_tilt_rms_deg <= 1.0);
    CHECK(r.yaw_rms_deg <= 0.5);
    CHECK(r.yaw_max_deg <= 1.0);
    CHECK(fabs(r.yaw_drift_deg_per_min) <= 1.5);
    CHECK(r.yaw_rms_deg * 3.0 <= r.nomag_yaw_rms_deg);
    CHECK(r.mag_updates > 5000 && r.mag_gated == 0); /* ≤ 200 Hz over 29.5 s */
    opt.mag_hard_iron_known = 0;
    CHECK(trk_evaluate_device(TRK_DEVICE_RIFT_DK2, rows, SLICE_ROWS, &opt, &r, &err) == 0);
    printf("Rift DK2 + magnetometer (online hard iron): yaw RMS/max %.2f/%.2f (%.2f/%.2f) deg, offset error %.4f gauss\n",
           r.yaw_rms_deg, r.yaw_max_deg, r.nomag_yaw_rms_deg, r.nomag_yaw_max_deg, r.hard_iron_error_gauss);
    CHECK(r.tilt_rms_deg <= 1.0 && isfinite(r.yaw_rms_deg));
    CHECK(r.yaw_rms_deg <= r.nomag_yaw_rms_deg);
    CHECK(r.hard_iron_error_gauss >= 0 && r.hard_iron_error_gauss < 0.01);
    /* Devices without a magnetometer: nothing changes, both figures are the same run's. */
    CHECK(trk_evaluate_device(TRK_DEVICE_VIVE, rows, SLICE_ROWS, &opt, &r, &err) == 0);
    CHECK(!r.has_mag && r.mag_updates == 0 && r.nomag_yaw_rms_deg == r.yaw_rms_deg);
    trk_imu_csv_free(rows);
}

int main(int argc, char **argv)
{
    /* "small" (scripts/valgrind-tests.sh: memcheck runs this ~150x slower): every check on one stream
     * each, without the second native one (the same code path on other data). */
    int small = argc > 1 && strcmp(argv[1], "small") == 0;
    test_bad_input();
    test_magnetometer();
    test_native("data/imu/corbillon_user1_t30.csv", 0);
    if (!small)
        test_native("data/imu/nasrabadi_322SAJ_9_t0.csv", 15000); /* holds the 612 deg/s turn at 29.8-31 s */
    test_drops_and_wrap("data/imu/corbillon_user2_t60.csv");
    return tu_finish(small ? "test_tracking_accuracy small" : "test_tracking_accuracy");
}
