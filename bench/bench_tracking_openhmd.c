/* OpenHMD's fusion on the shared IMU streams, for bench tracking's "OpenHMD (measured)" row.
 *
 * Why through libopenhmd and not a port: the row must be OpenHMD's own code as shipped (Debian
 * libopenhmd 0.3.0), measured in the same run as ours, not a figure quoted from elsewhere. The way in
 * is its "OpenHMD / External Device" (drv_external): ohmd_device_setf(OHMD_EXTERNAL_SENSOR_FUSION,
 * float[10]) calls ofusion_update(dt, gyro, accel, mag) — the fusion its Rift, Vive and PSVR drivers
 * use — and ohmd_ctx_update copies the fused orientation to where OHMD_ROTATION_QUAT reads it.
 *
 * Frame (read from OpenHMD's src/fusion.c, src/omath.c, src/drv_external/external.c and its Rift
 * driver, which hands the sensor's raw axes to the fusion): the body frame is the Rift sensor's,
 * +X right, +Y up, +Z toward the wearer; the world is +Y up (its gravity correction compares the
 * world-rotated accel mean with up = (0, 1, 0) and expects |accel| ≈ 9.82 at rest, i.e. specific
 * force, +g up when still); the gyro is rad/s in the body frame, integrated as orient ⊗ exp(ω·dt)
 * (Hamilton product, orient rotates body vectors into the world). That is exactly the shared
 * streams' convention (data/README.md §5), so the conversion is the identity on axes and units; what
 * changes is the precision (float) and the quaternion's component order (x y z w there, w x y z
 * here). tests/test_tracking_openhmd.c checks this with pure rotations about each axis, so an axis
 * mistake cannot pass as "OpenHMD is bad".
 *
 * Warm start, as ours (tracking/evaluate.c: the truth at t = 0): OpenHMD has no call to set the
 * fusion's orientation (ohmd_device_setf(OHMD_ROTATION_QUAT) only adds an output correction, which
 * its gravity correction would not see), and it starts at identity. So one extra sample first turns
 * it from identity to rows[0]'s truth: dt = 1 s, ω = the truth's rotation vector (rad/s), accel =
 * rows[0]'s. It integrates exactly that rotation (|ω| > 0.1 rad/s also keeps it from counting the
 * sample as "at rest"); the error left is reported (warm_error_deg, float rounding). Then samples
 * 1 … n−1 go in with dt = t_k − t_{k−1}: gyro sample k is the mean rate over (t_{k−1}, t_k], which
 * is what orient ⊗ exp(ω·dt) integrates. The magnetometer is zero: the streams have none, and
 * OpenHMD 0.3.0's fusion stores it without using it.
 *
 * Scoring: after each sample, OpenHMD's orientation against the truth at t_k, through
 * trk_accuracy_* (tracking/accuracy.c), the code that scores ours. OpenHMD's external device does
 * not predict, so its prediction figures are the hold ones (pred = estimate).
 * Timing: the records are built first; fuse = setf + ctx_update per sample over the whole stream, no
 * clock reads inside, median of the repeats (each on a fresh device); sample→pose = per sample,
 * clock before setf and after getf (one clock read included, ~20 ns). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_tracking_openhmd.h"

#ifdef HMDLOD_HAVE_OPENHMD
#include <openhmd.h>
#endif

void bch_openhmd_sample(double dt_s, hl_vec3d gyro_radps, hl_vec3d accel_mps2, float out[10])
{
    /* Identity on axes and units: OpenHMD's body frame and accel sign are the streams' (see above). */
    out[0] = (float)dt_s;
    out[1] = (float)gyro_radps.x;
    out[2] = (float)gyro_radps.y;
    out[3] = (float)gyro_radps.z;
    out[4] = (float)accel_mps2.x;
    out[5] = (float)accel_mps2.y;
    out[6] = (float)accel_mps2.z;
    out[7] = out[8] = out[9] = 0.0f;
}

int bch_openhmd_quat_to_hmdlod(const float q_xyzw[4], hl_quatd *out)
{
    hl_quatd q = hl_q(q_xyzw[3], q_xyzw[0], q_xyzw[1], q_xyzw[2]);
    if (!(isfinite(q.w) && isfinite(q.x) && isfinite(q.y) && isfinite(q.z)))
        return -1;
    double norm = sqrt(hl_q_dot(q, q));
    if (!(fabs(norm - 1.0) < 1e-3)) /* OpenHMD renormalizes every update; anything else is garbage */
        return -1;
    *out = hl_q_normalize(q);
    return 0;
}

#ifndef HMDLOD_HAVE_OPENHMD

int bch_openhmd_available(void)
{
    return 0;
}

int bch_openhmd_evaluate(const struct trk_imu_csv_row *rows, size_t n, double yaw_skip_s, int repeats,
                           struct bch_openhmd_result *res, struct hl_error *err)
{
    (void)rows, (void)n, (void)yaw_skip_s, (void)repeats;
    if (res)
        memset(res, 0, sizeof *res);
    return hl_fail(err, BCH_OPENHMD_ABSENT);
}

#else

int bch_openhmd_available(void)
{
    return 1;
}

struct oh_session {
    ohmd_context *ctx;
    ohmd_device *dev;
};

static void oh_close(struct oh_session *s)
{
    if (s->ctx)
        ohmd_ctx_destroy(s->ctx); /* closes the device too */
    s->ctx = NULL;
    s->dev = NULL;
}

/* A context with the external device open, manual updates (no update thread: the fusion runs only
 * when we feed it, and nothing else takes its mutex). */
static int oh_open(struct oh_session *s, struct hl_error *err)
{
    memset(s, 0, sizeof *s);
    s->ctx = ohmd_ctx_create();
    if (!s->ctx)
        return hl_fail(err, "OpenHMD: ohmd_ctx_create failed");
    int count = ohmd_ctx_probe(s->ctx), index = -1;
    for (int i = 0; i < count && index < 0; ++i) {
        const char *vendor = ohmd_list_gets(s->ctx, i, OHMD_VENDOR);
        const char *product = ohmd_list_gets(s->ctx, i, OHMD_PRODUCT);
        if (vendor && product && !strcmp(vendor, "OpenHMD") && !strcmp(product, "External Device"))
            index = i;
    }
    if (index < 0) {
        oh_close(s);
        return hl_fail(err, "OpenHMD: no \"OpenHMD / External Device\" among the %d devices probed", count);
    }
    ohmd_device_settings *settings = ohmd_device_settings_create(s->ctx);
    int manual = 0;
    if (settings)
        ohmd_device_settings_seti(settings, OHMD_IDS_AUTOMATIC_UPDATE, &manual);
    s->dev = settings ? ohmd_list_open_device_s(s->ctx, index, settings) : NULL;
    if (settings)
        ohmd_device_settings_destroy(settings);
    if (!s->dev) {
        hl_fail(err, "OpenHMD: cannot open the external device: %s", ohmd_ctx_get_error(s->ctx));
        oh_close(s);
        return -1;
    }
    return 0;
}

static int oh_feed(struct oh_session *s, const float rec[10])
{
    int rc = ohmd_device_setf(s->dev, OHMD_EXTERNAL_SENSOR_FUSION, rec);
    ohmd_ctx_update(s->ctx);
    return rc;
}

static int oh_read(struct oh_session *s, hl_quatd *q)
{
    float f[4];
    if (ohmd_device_getf(s->dev, OHMD_ROTATION_QUAT, f) != 0)
        return -1;
    return bch_openhmd_quat_to_hmdlod(f, q);
}

/* The warm-start sample (see the header comment): identity → q0 in one integration step. */
static int oh_warm(struct oh_session *s, const struct trk_imu_csv_row *row0, double *err_deg, struct hl_error *err)
{
    float rec[10];
    bch_openhmd_sample(1.0, hl_q_log(row0->truth), row0->accel_mps2, rec);
    hl_quatd q;
    if (oh_feed(s, rec) != 0 || oh_read(s, &q) != 0)
        return hl_fail(err, "OpenHMD: the external device refused the warm-start sample");
    *err_deg = hl_q_angle_rad(q, row0->truth) * HL_DEG_PER_RAD;
    if (!(*err_deg < 0.01))
        return hl_fail(err, "OpenHMD: warm start missed the truth by %.4f° (frame conversion?)", *err_deg);
    return 0;
}


int bch_openhmd_evaluate(const struct trk_imu_csv_row *rows, size_t n, double yaw_skip_s, int repeats,
                           struct bch_openhmd_result *res, struct hl_error *err)
{
    if (!rows || !res || n < 100)
        return hl_fail(err, "OpenHMD evaluation: need at least 100 rows, got %zu", rows ? n : 0);
    double dt_s = (rows[n - 1].t_s - rows[0].t_s) / (double)(n - 1);
    if (!(fabs(dt_s - 0.001) < 1e-6))
        return hl_fail(err, "OpenHMD evaluation: rows are %.6f s apart, expected the streams' 1 kHz", dt_s);
    memset(res, 0, sizeof *res);
    int major = 0, minor = 0, patch = 0;
    ohmd_get_version(&major, &minor, &patch);
    snprintf(res->version, sizeof res->version, "%d.%d.%d", major, minor, patch);

    float *recs = malloc((n - 1) * 10 * sizeof *recs);
    double *lat_us = malloc((n - 1) * sizeof *lat_us);
    if (!recs || !lat_us) {
        free(recs);
        free(lat_us);
        return hl_fail(err, "OpenHMD evaluation: out of memory for %zu samples", n);
    }
    for (size_t k = 1; k < n; ++k)
        bch_openhmd_sample(rows[k].t_s - rows[k - 1].t_s, rows[k].gyro_radps, rows[k].accel_mps2,
                             recs + (k - 1) * 10);

    /* Pass 1: accuracy and per-sample latency. */
    struct oh_session s;
    int rc = oh_open(&s, err);
    if (rc == 0)
        rc = oh_warm(&s, &rows[0], &res->warm_error_deg, err);
    struct trk_accuracy acc;
    trk_accuracy_init(&acc, yaw_skip_s);
    size_t horizon_rows[TRK_EVAL_HORIZONS];
    for (int h = 0; h < TRK_EVAL_HORIZONS; ++h)
        horizon_rows[h] = (size_t)lround(trk_eval_horizons_s[h] / dt_s);
    for (size_t k = 1; rc == 0 && k < n; ++k) {
        hl_quatd est;
        int64_t t0 = hl_clock_now_ns();
        int fed = oh_feed(&s, recs + (k - 1) * 10);
        int got = oh_read(&s, &est);
        int64_t t1 = hl_clock_now_ns();
        lat_us[k - 1] = (double)(t1 - t0) * 1e-3;
        if (fed != 0 || got != 0) {
            rc = hl_fail(err, "OpenHMD: %s at t = %.3f s", fed != 0 ? "setf refused a sample"
                                                                    : "non-finite or non-unit orientation",
                         rows[k].t_s);
            break;
        }
        res->last = est;
        const hl_quatd truth = rows[k].truth;
        trk_accuracy_add(&acc, rows[k].t_s - rows[0].t_s, est, truth);
        for (int h = 0; h < TRK_EVAL_HORIZONS; ++h)
            if (k + horizon_rows[h] < n) /* no prediction: pred = est (hold) */
                trk_accuracy_add_horizon(&acc, h, est, est, truth, rows[k + horizon_rows[h]].truth);
    }
    oh_close(&s);
    if (rc == 0) {
        trk_accuracy_finish(&acc, &res->acc);
        res->acc.duration_s = rows[n - 1].t_s - rows[0].t_s;
        res->acc.device_rate_hz = 1.0 / dt_s;
        res->acc.samples_fused = res->samples = n - 1;
        hl_sort_doubles(lat_us, n - 1);
        res->sample_to_pose_us_median = hl_percentile_sorted(lat_us, n - 1, 0.5);
        res->sample_to_pose_us_p99 = hl_percentile_sorted(lat_us, n - 1, 0.99);
    }

    /* Pass 2: throughput, fresh device each repeat; lat_us reused for the per-repeat figures. */
    if (repeats > (int)(n - 1))
        repeats = (int)(n - 1);
    double sink = 0;
    int done = 0;
    for (int r = 0; rc == 0 && r < repeats; ++r) {
        double warm_deg;
        rc = oh_open(&s, err);
        if (rc == 0)
            rc = oh_warm(&s, &rows[0], &warm_deg, err);
        if (rc == 0) {
            int64_t t0 = hl_clock_now_ns();
            for (size_t k = 1; k < n; ++k)
                oh_feed(&s, recs + (k - 1) * 10);
            int64_t t1 = hl_clock_now_ns();
            hl_quatd q = hl_q_identity();
            oh_read(&s, &q);
            sink += q.w;
            lat_us[done++] = (double)(t1 - t0) / (double)(n - 1); /* ns per sample */
        }
        oh_close(&s);
    }
    if (rc == 0 && done > 0) {
        hl_sort_doubles(lat_us, (size_t)done);
        res->fuse_ns_per_sample = lat_us[done / 2];
    }
    free(recs);
    free(lat_us);
    if (rc == 0 && !isfinite(sink))
        rc = hl_fail(err, "OpenHMD: non-finite orientation after a timing pass");
    return rc;
}

#endif
