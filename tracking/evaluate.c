/* End-to-end tracker accuracy: shared IMU stream → device reports at the native rate → parser →
 * fusion → comparison with the ground truth, and the time this path takes.
 *
 * The path is the driver's: trk_stream_feed (parser + fusion) and trk_stream_pose (prediction).
 * Why through the reports and not straight into the fusion (tests/test_fusion.c does that): the
 * reports add what a real tracker adds — LSB quantization and range clipping per device, 16/24/32-bit
 * counters that wrap, batching (PSVR 2 samples a report), the Vive's repeating ring, lost reports —
 * and the timing must include parsing, because that is what a driver pays per report.
 *
 * How each device's samples are made from the 1 kHz stream (data/README.md §5: gyro sample k = mean
 * body rate over (t_k − 1 ms, t_k], accel = specific force at t_k, body frame, noise/bias/drift
 * included):
 *   Rift DK1/DK2/CV1, Vive, Vive Pro/Index: 1 kHz, one stream sample per device sample.
 *   PSVR (≈2 kHz, DEVICES.md §2a): two samples per stream millisecond, at t_k − 0.5 ms and t_k, one
 *     report per millisecond. The gyro is a mean rate over each half interval; the stream's mean over
 *     the whole millisecond is placed at its centre and interpolated linearly to the half-interval
 *     centres: (t_k − 0.75 ms) ← ¼g_{k−1} + ¾g_k, (t_k − 0.25 ms) ← ¾g_k + ¼g_{k+1}. The two halves
 *     then integrate to ¾g_k + ⅛(g_{k−1} + g_{k+1}) per millisecond: no bias, so no drift. Accel is
 *     instantaneous: its midpoint value is the mean of a_{k−1} and a_k. Caveat: interpolation does
 *     not add the √2 higher per-sample noise a real 2 kHz gyro has; the noise density is the stream's.
 *   OSVR HDK (400 Hz, on-chip fusion, no raw IMU): the stream's samples cannot be fed to a BNO070, so
 *     its output is MODELLED (an assumption, not a measurement): orientation = E(t) ⊗ q_true(t), where
 *     E = a yaw drift about world +Y (default 0.5 °/min, a typical gyro-only heading drift of an
 *     on-chip game-rotation vector) times a first-order Gauss–Markov error on each world axis
 *     (default σ 0.1°, τ 1 s: slow wander, not per-report jitter); angular velocity = the true mean
 *     body rate over the report period + white noise of the stream's gyro density. Hence the HDK's
 *     tilt figure is set by this model (≈ σ·√2 RMS), not earned by hmdlod's fusion; its prediction
 *     figures do exercise the real report path (Q1.14 / Q6.9 quantization) and the predictor.
 *
 *   Rift magnetometer (the streams have none, data/README.md §5): SYNTHESIZED from the truth, an
 *     assumption: world field 0.48 gauss with 60° dip (mid-latitude Europe), heading drawn; body
 *     reading = R(q)ᵀB + a constant hard-iron offset (each axis uniform ±0.25 gauss, drawn from the
 *     seed: headset magnets) + 2 mgauss white noise per axis (HMC5983 class, DK2), quantized to 1e-4
 *     gauss by the encoder, one per report. Soft iron and disturbances are not simulated. The fusion
 *     fits the offset online unless mag_hard_iron_known; accuracy is also measured with the
 *     magnetometer ignored (nomag_) and with the true offset given (cal_).
 *
 * Warm start, as tests/test_fusion.c and the README's table: the fusion starts at the truth at the
 * first device sample with a 0.1° prior σ, so tilt and yaw measure tracking, not convergence.
 *
 * Metrics at every delivered report (its newest sample time t), truth slerped between the 1 ms rows:
 *   tilt  angle between true and estimated body up-axis (world +Y seen in the body), RMS/max;
 *   yaw   least-squares slope of the unwrapped heading error 2·atan2(d.y, d.w), d = q_est ⊗ q_true⁻¹;
 *   step  body-frame step error: est⁻¹ ⊗ pred vs truth(t)⁻¹ ⊗ truth(t+h) (a heading offset between
 *         the estimated and true world frames does not enter), baseline hold = identity step;
 *   abs   angle(pred, truth(t+h)) vs hold angle(est, truth(t+h)).
 * Timing: parse+fuse = whole pre-encoded stream fed with no clock reads inside the loop, divided by
 * the samples fused, median over repeats; report→pose = per report, clock before the feed and after
 * the predicted pose (includes one clock read, ~20 ns), median and p99. Encoding is never timed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tracking/tracking.h"

const double trk_eval_horizons_s[TRK_EVAL_HORIZONS] = {0.010, 0.020, 0.040};

void trk_evaluate_options_default(struct trk_evaluate_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->pose_horizon_s = 0.020;
    opt->timing_repeats = 3;
    opt->hdk_yaw_drift_deg_per_min = 0.5;
    opt->hdk_error_sigma_deg = 0.1;
    opt->hdk_error_tau_s = 1.0;
    opt->hdk_gyro_noise_degps_rthz = 0.01;
    opt->seed = 1;
    opt->rift_magnetometer = 1;
    opt->mag_field_gauss = 0.48;
    opt->mag_dip_deg = 60.0;
    opt->mag_noise_gauss = 0.002;
    opt->mag_hard_iron_max_gauss = 0.25;
    opt->yaw_skip_s = 5.0;
}

const char *trk_evaluate_device_name(enum trk_device_kind kind)
{
    switch (kind) {
    case TRK_DEVICE_RIFT_DK1: return "Rift DK1";
    case TRK_DEVICE_RIFT_DK2: return "Rift DK2";
    case TRK_DEVICE_RIFT_CV1: return "Rift CV1";
    case TRK_DEVICE_PSVR: return "PSVR";
    case TRK_DEVICE_VIVE: return "Vive";
    case TRK_DEVICE_VIVE_PRO_INDEX: return "Vive Pro/Index";
    case TRK_DEVICE_HDK: return "OSVR HDK";
    }
    return "unknown";
}

/* ---- parse + fuse for one device ------------------------------------------------------------- */

/* The report path is the driver's own: trk_stream (parser by kind → fusion; HDK: the on-device
 * orientation taken as is, with its ω for prediction), so the figures are those of live use. */
static const struct trk_report_counters *ev_counters(const struct trk_stream *s)
{
    switch (s->kind) {
    case TRK_DEVICE_PSVR: return &s->parser.psvr.n;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: return &s->parser.vive.n;
    case TRK_DEVICE_HDK: return &s->parser.hdk.n;
    default: return &s->parser.rift.n;
    }
}

static void ev_init(struct trk_stream *s, enum trk_device_kind kind, const struct trk_fusion_config *cfg,
                    hl_quatd warm_q)
{
    trk_stream_init(s, kind, cfg);
    trk_fusion_set_orientation(&s->fusion, warm_q, 0.1 * HL_RAD_PER_DEG);
}

/* Orientation predicted horizon_s past the newest sample (0: the estimate itself). */
static hl_quatd ev_predict(const struct trk_stream *s, double horizon_s)
{
    struct trk_pose pose;
    trk_stream_pose(s, horizon_s, &pose);
    return pose.orientation;
}

/* ---- sample generation ----------------------------------------------------------------------- */

struct ev_truth {
    const struct trk_imu_csv_row *rows;
    size_t n;
    double dt_s; /* row spacing (1 ms) */
};

/* Truth at t seconds after rows[0] (slerp between rows; clamped to the span). */
static hl_quatd truth_at(const struct ev_truth *tr, double t_s)
{
    double x = t_s / tr->dt_s;
    if (!(x > 0))
        return tr->rows[0].truth;
    size_t i = (size_t)x;
    if (i >= tr->n - 1)
        return tr->rows[tr->n - 1].truth;
    double f = x - (double)i;
    return f < 1e-12 ? tr->rows[i].truth : hl_q_slerp(tr->rows[i].truth, tr->rows[i + 1].truth, f);
}

/* splitmix64 + Box–Muller: deterministic, no libc state. */
static uint64_t ev_rand_u64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double ev_uniform(uint64_t *state) /* [0, 1) */
{
    return (double)(ev_rand_u64(state) >> 11) / 9007199254740992.0;
}
static double ev_randn(uint64_t *state)
{
    double u1 = ((double)(ev_rand_u64(state) >> 11) + 0.5) / 9007199254740992.0;
    double u2 = (double)(ev_rand_u64(state) >> 11) / 9007199254740992.0;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * HL_PI * u2);
}

/* Largest gyro magnitude per axis the device's report can carry (rad/s). */
static double gyro_range_radps(enum trk_device_kind kind, const struct trk_encoder *enc)
{
    switch (kind) {
    case TRK_DEVICE_PSVR: return 32767.0 * TRK_PSVR_GYRO_LSB_RADPS;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: return enc->opt.vive.gyro_range_radps;
    case TRK_DEVICE_HDK: return 32767.0 * TRK_HDK_GYRO_LSB_RADPS;
    default: return 1048575.0 * TRK_RIFT_LSB;
    }
}

/* Counter width and tick (ns = num/den) per kind, for placing a wrap; bits 0: no counter. */
static void counter_format(enum trk_device_kind kind, uint32_t *bits, double *tick_ns)
{
    switch (kind) {
    case TRK_DEVICE_RIFT_DK1: *bits = 16; *tick_ns = 1e6; break;
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1: *bits = 32; *tick_ns = 1e3; break;
    case TRK_DEVICE_PSVR: *bits = 24; *tick_ns = 1e3; break;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: *bits = 32; *tick_ns = 1e3 / 48.0; break;
    default: *bits = 0; *tick_ns = 0; break;
    }
}

/* One delivered report, as a driver would receive it. */
struct ev_record {
    double t_s;          /* newest sample's time after rows[0] (where the estimate is compared) */
    int64_t host_ns;     /* host receive time (= device time here; the HDK uses it as its clock) */
    uint32_t length;
    uint8_t bytes[64];
};

struct ev_gen {
    struct trk_encoder enc;
    struct ev_record *rec;
    size_t count, cap;
    uint64_t samples, clipped;
    double range_radps;
    int has_mag;                /* Rift reports carry a synthesized magnetometer */
    hl_vec3d hard_iron_gauss;   /* its true offset */
};

static int gen_push(struct ev_gen *g, const struct trk_imu_sample *s, struct hl_error *err)
{
    if (fabs(s->gyro_radps.x) > g->range_radps || fabs(s->gyro_radps.y) > g->range_radps ||
        fabs(s->gyro_radps.z) > g->range_radps)
        ++g->clipped;
    ++g->samples;
    if (g->count == g->cap)
        return hl_fail(err, "tracking evaluation: more reports than planned (%zu)", g->cap);
    struct ev_record *r = &g->rec[g->count];
    int len = trk_encoder_push(&g->enc, s, r->bytes, sizeof r->bytes, err);
    if (len < 0)
        return -1;
    if (len > 0) {
        r->length = (uint32_t)len;
        r->t_s = (double)s->device_time_ns * 1e-9;
        r->host_ns = s->device_time_ns;
        ++g->count;
    }
    return 0;
}

static void sample_imu(struct trk_imu_sample *s, int64_t t_ns, hl_vec3d gyro, hl_vec3d accel)
{
    memset(s, 0, sizeof *s);
    s->device_time_ns = t_ns;
    s->gyro_radps = gyro;
    s->accel_mps2 = accel;
    s->orientation = hl_q_identity();
    s->has_gyro = s->has_accel = 1;
}

static hl_vec3d v3_mix(hl_vec3d a, double wa, hl_vec3d b, double wb)
{
    return hl_v3_add(hl_v3_scale(a, wa), hl_v3_scale(b, wb));
}

static int generate(enum trk_device_kind kind, const struct ev_truth *tr, const struct trk_evaluate_options *opt,
                    struct ev_gen *g, struct hl_error *err)
{
    const struct trk_imu_csv_row *rows = tr->rows;
    size_t n = tr->n;
    int64_t dt_ns = llround(tr->dt_s * 1e9);
    struct trk_imu_sample s;
    if (kind == TRK_DEVICE_PSVR) {
        for (size_t k = 1; k < n; ++k) {
            hl_vec3d g_next = rows[k + 1 < n ? k + 1 : k].gyro_radps;
            int64_t t_ns = (int64_t)k * dt_ns;
            sample_imu(&s, t_ns - dt_ns / 2, v3_mix(rows[k - 1].gyro_radps, 0.25, rows[k].gyro_radps, 0.75),
                       v3_mix(rows[k - 1].accel_mps2, 0.5, rows[k].accel_mps2, 0.5));
            if (gen_push(g, &s, err) < 0)
                return -1;
            sample_imu(&s, t_ns, v3_mix(rows[k].gyro_radps, 0.75, g_next, 0.25), rows[k].accel_mps2);
            if (gen_push(g, &s, err) < 0)
                return -1;
        }
    } else if (kind == TRK_DEVICE_HDK) {
        const double period_s = 1.0 / 400.0;
        const int64_t period_ns = 2500000;
        double span_s = (double)(n - 1) * tr->dt_s;
        uint64_t rng = opt->seed ? opt->seed : 1;
        double sigma = opt->hdk_error_sigma_deg * HL_RAD_PER_DEG;
        double a = opt->hdk_error_tau_s > 0 ? exp(-period_s / opt->hdk_error_tau_s) : 0.0;
        double drive = sigma * sqrt(1.0 - a * a);
        double gyro_sigma = opt->hdk_gyro_noise_degps_rthz * HL_RAD_PER_DEG * sqrt(1.0 / period_s);
        hl_vec3d e = hl_v3(sigma * ev_randn(&rng), sigma * ev_randn(&rng), sigma * ev_randn(&rng));
        for (int64_t j = 0; (double)j * period_s <= span_s + 1e-9; ++j) {
            double t = (double)j * period_s;
            hl_quatd q = truth_at(tr, t);
            /* Mean body rate over the report period (forward for the first report). */
            hl_quatd q0 = j > 0 ? truth_at(tr, t - period_s) : q, q1 = j > 0 ? q : truth_at(tr, t + period_s);
            hl_vec3d w = hl_v3_scale(hl_q_log(hl_q_mul(hl_q_conj(q0), q1)), 1.0 / period_s);
            w = hl_v3_add(w, hl_v3(gyro_sigma * ev_randn(&rng), gyro_sigma * ev_randn(&rng),
                                   gyro_sigma * ev_randn(&rng)));
            double yaw = opt->hdk_yaw_drift_deg_per_min * HL_RAD_PER_DEG / 60.0 * t;
            hl_quatd err_q = hl_q_mul(hl_q_exp(hl_v3(0, yaw, 0)), hl_q_exp(e));
            memset(&s, 0, sizeof s);
            s.device_time_ns = j * period_ns;
            s.orientation = hl_q_normalize(hl_q_mul(err_q, q));
            s.gyro_radps = w;
            s.has_orientation = s.has_gyro = 1;
            if (gen_push(g, &s, err) < 0)
                return -1;
            e = hl_v3(a * e.x + drive * ev_randn(&rng), a * e.y + drive * ev_randn(&rng),
                      a * e.z + drive * ev_randn(&rng));
        }
    } else {
        int rift = kind == TRK_DEVICE_RIFT_DK1 || kind == TRK_DEVICE_RIFT_DK2 || kind == TRK_DEVICE_RIFT_CV1;
        int mag = rift && opt->rift_magnetometer;
        uint64_t rng = (opt->seed ? opt->seed : 1) ^ 0x6D61676E6574ull; /* independent of the HDK draws */
        hl_vec3d field = hl_v3(0, 0, 0);
        if (mag) {
            /* World field: ‖B‖ with the dip below the horizon, heading drawn (no meaning: the
             * fusion's reference is relative). Offset: each axis uniform in ±max. */
            double dip = opt->mag_dip_deg * HL_RAD_PER_DEG, head = 2.0 * HL_PI * ev_uniform(&rng);
            field = hl_v3_scale(hl_v3(cos(dip) * cos(head), -sin(dip), -cos(dip) * sin(head)), opt->mag_field_gauss);
            g->hard_iron_gauss = hl_v3(opt->mag_hard_iron_max_gauss * (2.0 * ev_uniform(&rng) - 1.0),
                                       opt->mag_hard_iron_max_gauss * (2.0 * ev_uniform(&rng) - 1.0),
                                       opt->mag_hard_iron_max_gauss * (2.0 * ev_uniform(&rng) - 1.0));
        }
        for (size_t k = 0; k < n; ++k) {
            sample_imu(&s, (int64_t)k * dt_ns, rows[k].gyro_radps, rows[k].accel_mps2);
            if (mag) {
                /* Body reading R(q)ᵀB + b + noise; one per report at the native 1 sample a report. */
                hl_vec3d mb = hl_q_rotate(hl_q_conj(rows[k].truth), field);
                s.mag_gauss = hl_v3(mb.x + g->hard_iron_gauss.x + opt->mag_noise_gauss * ev_randn(&rng),
                                    mb.y + g->hard_iron_gauss.y + opt->mag_noise_gauss * ev_randn(&rng),
                                    mb.z + g->hard_iron_gauss.z + opt->mag_noise_gauss * ev_randn(&rng));
                s.has_mag = 1;
            }
            if (gen_push(g, &s, err) < 0)
                return -1;
        }
        g->has_mag = mag;
    }
    return 0;
}

/* ---- evaluation ------------------------------------------------------------------------------ */

double trk_tilt_error_rad(hl_quatd est, hl_quatd truth)
{
    hl_vec3d y = hl_v3(0, 1, 0);
    return hl_v3_angle_rad(hl_q_rotate(hl_q_conj(est), y), hl_q_rotate(hl_q_conj(truth), y));
}

double trk_yaw_error_rad(hl_quatd est, hl_quatd truth)
{
    hl_quatd d = hl_q_mul(est, hl_q_conj(truth));
    return 2.0 * atan2(d.y, d.w);
}


/* Accuracy only, the same reports with another fusion configuration (magnetometer ignored, or the
 * hard-iron offset given): tilt RMS, yaw drift slope, yaw RMS/max after yaw_skip_s, into res. */
static void yaw_pass(enum trk_device_kind kind, const struct trk_fusion_config *cfg,
                     const struct trk_evaluate_options *opt, const struct ev_gen *gen, const struct ev_truth *tr,
                     hl_quatd warm, struct trk_evaluate_result *res)
{
    struct trk_stream st;
    ev_init(&st, kind, cfg, warm);
    struct trk_accuracy acc;
    trk_accuracy_init(&acc, opt->yaw_skip_s);
    for (size_t i = 0; i < gen->count; ++i) {
        const struct ev_record *r = &gen->rec[i];
        if (trk_stream_feed(&st, r->bytes, r->length, r->host_ns, NULL) < 0)
            continue;
        trk_accuracy_add(&acc, r->t_s, st.fusion.orientation, truth_at(tr, r->t_s));
    }
    memset(res, 0, sizeof *res);
    trk_accuracy_finish(&acc, res);
}

int trk_evaluate_device(enum trk_device_kind kind, const struct trk_imu_csv_row *rows, size_t n,
                        const struct trk_evaluate_options *opt_in, struct trk_evaluate_result *res,
                        struct hl_error *err)
{
    struct trk_evaluate_options opt;
    if (opt_in)
        opt = *opt_in;
    else
        trk_evaluate_options_default(&opt);
    if (!(opt.pose_horizon_s >= 0))
        opt.pose_horizon_s = 0.020;
    if (!rows || !res || n < 100)
        return hl_fail(err, "tracking evaluation: need at least 100 rows, got %zu", rows ? n : 0);
    if ((unsigned)kind > (unsigned)TRK_DEVICE_HDK)
        return hl_fail(err, "tracking evaluation: unknown device kind %d", (int)kind);
    struct ev_truth tr = {rows, n, (rows[n - 1].t_s - rows[0].t_s) / (double)(n - 1)};
    if (!(fabs(tr.dt_s - 0.001) < 1e-6))
        return hl_fail(err, "tracking evaluation: rows are %.6f s apart, expected the streams' 1 kHz", tr.dt_s);
    memset(res, 0, sizeof *res);
    res->kind = kind;
    res->duration_s = (double)(n - 1) * tr.dt_s;

    struct trk_encoder_options eo;
    memset(&eo, 0, sizeof eo);
    eo.drop_report_every = opt.drop_report_every;
    uint32_t bits;
    double tick_ns;
    counter_format(kind, &bits, &tick_ns);
    if (opt.counter_wrap_at_s > 0 && bits > 0) {
        /* Start the counter so that it reaches 2^bits (wraps) counter_wrap_at_s into the stream. */
        int64_t ticks;
        if (hl_i64_from_double(opt.counter_wrap_at_s * 1e9 / tick_ns + 0.5, &ticks) != 0 || ticks > ((int64_t)1 << bits))
            return hl_fail(err, "tracking evaluation: a counter wrap at %g s is beyond the %u-bit counter's range",
                           opt.counter_wrap_at_s, bits);
        int64_t offset = ((int64_t)1 << bits) - ticks;
        if (kind == TRK_DEVICE_VIVE || kind == TRK_DEVICE_VIVE_PRO_INDEX)
            offset -= offset % 6; /* the encoder's tick→ns conversion is exact for multiples of 6 */
        eo.counter_offset_ticks = offset > 0 ? offset : 0;
    }
    struct ev_gen gen;
    memset(&gen, 0, sizeof gen);
    trk_encoder_init(&gen.enc, kind, &eo);
    gen.range_radps = gyro_range_radps(kind, &gen.enc);
    gen.cap = n + 8; /* at most one report per stream millisecond (HDK: 0.4 per ms) */
    gen.rec = malloc(gen.cap * sizeof *gen.rec);
    double *lat_us = malloc(gen.cap * sizeof *lat_us);
    if (!gen.rec || !lat_us) {
        free(gen.rec);
        free(lat_us);
        return hl_fail(err, "tracking evaluation: out of memory for %zu reports", gen.cap);
    }
    int rc = generate(kind, &tr, &opt, &gen, err);
    if (rc == 0 && gen.count == 0)
        rc = hl_fail(err, "tracking evaluation: %s produced no reports", trk_evaluate_device_name(kind));
    if (rc != 0) {
        free(gen.rec);
        free(lat_us);
        return -1;
    }
    res->device_samples = gen.samples;
    res->device_rate_hz = res->duration_s > 0 ? (double)gen.samples / res->duration_s : 0;
    res->reports_built = gen.enc.reports_built;
    res->reports_dropped = gen.enc.reports_dropped;
    res->gyro_clipped = gen.clipped;

    /* Warm start at the truth at the first device sample (PSVR: 0.5 ms in; others: 0). */
    double t_first_s = kind == TRK_DEVICE_PSVR ? 0.5 * tr.dt_s : 0.0;
    hl_quatd warm = truth_at(&tr, t_first_s);

    /* A calibrated headset: the fusion is told the true hard-iron offset. */
    struct trk_fusion_config cal_cfg;
    if (gen.has_mag && opt.mag_hard_iron_known) {
        if (opt.fusion)
            cal_cfg = *opt.fusion;
        else
            trk_fusion_config_default(&cal_cfg);
        cal_cfg.mag_hard_iron_gauss = gen.hard_iron_gauss;
        cal_cfg.mag_estimate_hard_iron = 0;
        opt.fusion = &cal_cfg;
    }

    /* Pass 1: accuracy, and per-report latency (bytes in hand → predicted pose). */
    struct trk_stream st; /* ~1 KB: parser + 9-state filter, plain data */
    ev_init(&st, kind, opt.fusion, warm);
    struct trk_accuracy acc;
    trk_accuracy_init(&acc, opt.yaw_skip_s);
    double sink = 0;
    for (size_t i = 0; i < gen.count; ++i) {
        const struct ev_record *r = &gen.rec[i];
        struct trk_pose pose;
        int64_t t0 = hl_clock_now_ns();
        int got = trk_stream_feed(&st, r->bytes, r->length, r->host_ns, err);
        trk_stream_pose(&st, opt.pose_horizon_s, &pose);
        int64_t t1 = hl_clock_now_ns();
        lat_us[i] = (double)(t1 - t0) * 1e-3;
        sink += pose.orientation.w;
        if (got < 0)
            continue; /* counted; the estimate did not change */
        hl_quatd est = ev_predict(&st, 0.0), truth = truth_at(&tr, r->t_s);
        trk_accuracy_add(&acc, r->t_s, est, truth);
        for (int h = 0; h < TRK_EVAL_HORIZONS; ++h) {
            double t_h = r->t_s + trk_eval_horizons_s[h];
            if (t_h > res->duration_s + 1e-9)
                continue;
            trk_accuracy_add_horizon(&acc, h, est, ev_predict(&st, trk_eval_horizons_s[h]), truth,
                                     truth_at(&tr, t_h));
        }
    }
    trk_accuracy_finish(&acc, res);
    res->has_mag = gen.has_mag;
    res->mag_updates = st.fusion.stats.mag_updates;
    res->mag_gated = st.fusion.stats.mag_gated_norm + st.fusion.stats.mag_gated_dip +
                     st.fusion.stats.mag_gated_horizontal;
    res->hard_iron_error_gauss = -1.0;
    if (gen.has_mag && st.fusion.mag.hard_iron_ok)
        res->hard_iron_error_gauss = hl_v3_length(hl_v3_sub(st.fusion.mag.hard_iron_gauss, gen.hard_iron_gauss));
    res->nomag_tilt_rms_deg = res->tilt_rms_deg;
    res->nomag_yaw_drift_deg_per_min = res->yaw_drift_deg_per_min;
    res->nomag_yaw_rms_deg = res->yaw_rms_deg;
    res->nomag_yaw_max_deg = res->yaw_max_deg;
    res->cal_yaw_rms_deg = res->yaw_rms_deg;
    res->cal_yaw_max_deg = res->yaw_max_deg;
    res->cal_yaw_drift_deg_per_min = res->yaw_drift_deg_per_min;
    if (gen.has_mag) {
        struct trk_fusion_config cfg;
        if (opt.fusion)
            cfg = *opt.fusion;
        else
            trk_fusion_config_default(&cfg);
        struct trk_evaluate_result y;
        struct trk_fusion_config off = cfg;
        off.use_magnetometer = 0;
        yaw_pass(kind, &off, &opt, &gen, &tr, warm, &y);
        res->nomag_tilt_rms_deg = y.tilt_rms_deg;
        res->nomag_yaw_drift_deg_per_min = y.yaw_drift_deg_per_min;
        res->nomag_yaw_rms_deg = y.yaw_rms_deg;
        res->nomag_yaw_max_deg = y.yaw_max_deg;
        if (cfg.mag_estimate_hard_iron) { /* else pass 1 already was the calibrated case */
            struct trk_fusion_config cal = cfg;
            cal.mag_estimate_hard_iron = 0;
            cal.mag_hard_iron_gauss = gen.hard_iron_gauss;
            yaw_pass(kind, &cal, &opt, &gen, &tr, warm, &y);
            res->cal_yaw_drift_deg_per_min = y.yaw_drift_deg_per_min;
            res->cal_yaw_rms_deg = y.yaw_rms_deg;
            res->cal_yaw_max_deg = y.yaw_max_deg;
        }
    }
    const struct trk_report_counters *c = ev_counters(&st);
    res->reports_fed = st.reports;
    res->reports_rejected = st.rejected;
    res->samples_parsed = st.samples;
    res->samples_fused = st.fused;
    res->lost = c->lost;
    res->duplicates = c->duplicates;
    res->backward = c->backward;
    hl_sort_doubles(lat_us, gen.count);
    res->report_to_pose_us_median = hl_percentile_sorted(lat_us, gen.count, 0.5);
    res->report_to_pose_us_p99 = hl_percentile_sorted(lat_us, gen.count, 0.99);

    /* Pass 2: parse+fuse throughput over the whole stream, no clock reads inside the loop. lat_us is
     * reused for the per-repeat figures (repeats ≤ its capacity). */
    int repeats = opt.timing_repeats;
    if (repeats > (int)gen.cap)
        repeats = (int)gen.cap;
    for (int k = 0; k < repeats; ++k) {
        ev_init(&st, kind, opt.fusion, warm);
        int64_t t0 = hl_clock_now_ns();
        for (size_t i = 0; i < gen.count; ++i)
            trk_stream_feed(&st, gen.rec[i].bytes, gen.rec[i].length, gen.rec[i].host_ns, NULL);
        int64_t t1 = hl_clock_now_ns();
        sink += ev_predict(&st, 0.0).w;
        lat_us[k] = st.fused ? (double)(t1 - t0) / (double)st.fused : 0.0; /* ns per sample */
    }
    if (repeats > 0) {
        hl_sort_doubles(lat_us, (size_t)repeats);
        res->parse_fuse_ns_per_sample = lat_us[repeats / 2];
    }
    free(gen.rec);
    free(lat_us);
    if (!isfinite(sink))
        return hl_fail(err, "tracking evaluation: %s produced a non-finite pose", trk_evaluate_device_name(kind));
    return 0;
}
