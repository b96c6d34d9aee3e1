/* tests/fuzz/make_seeds.c: writes the binary seed inputs of the report, stream and recording
 * targets (tests/fuzz/corpus/NAME/) from the project's own device simulator (trk_encoder_push) and
 * recording writer, so the seeds are reports as the devices send them. Not built by default:
 * `cmake --build build --target fuzz_make_seeds && build/tests/fuzz/fuzz_make_seeds tests/fuzz/corpus`.
 * The text seeds are hand-made or short excerpts (docs/fuzzing.md). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tracking/tracking.h"

enum { MAX_REPORTS = 12, SEED_CAP = 8192 };

struct seed {
    uint8_t b[SEED_CAP];
    size_t n;
};

static void put(struct seed *s, const void *p, size_t n)
{
    if (s->n + n <= SEED_CAP) {
        memcpy(s->b + s->n, p, n);
        s->n += n;
    }
}

static void put_le(struct seed *s, uint64_t v, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        uint8_t c = (uint8_t)(v >> (8 * i));
        put(s, &c, 1);
    }
}

static int save(const char *dir, const char *target, const char *name, const struct seed *s)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s/%s", dir, target, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(s->b, 1, s->n, f) != s->n || fclose(f) != 0) {
        perror(path);
        return -1;
    }
    return 0;
}

/* Up to MAX_REPORTS reports of `kind` from a slow turn with gravity on +Y, from counter_offset ticks
 * (near a wrap when large). lengths[i], reports[i]; returns the count. */
static int make_reports(enum trk_device_kind kind, int64_t counter_offset, uint8_t reports[][64], size_t *lengths,
                        int64_t *times_ns)
{
    const struct trk_device_info *info = NULL;
    for (size_t i = 0; i < trk_device_table_count; ++i)
        if (trk_device_table[i].kind == kind && trk_device_table[i].role == TRK_ROLE_IMU)
            info = &trk_device_table[i];
    double rate = info ? info->sample_rate_hz : 1000.0;
    struct trk_encoder_options opt = {0};
    opt.counter_offset_ticks = counter_offset;
    struct trk_encoder enc;
    trk_encoder_init(&enc, kind, &opt);
    int count = 0;
    struct hl_error err;
    for (int i = 0; count < MAX_REPORTS && i < 200; ++i) {
        struct trk_imu_sample s = {0};
        s.device_time_ns = 1000000000 + (int64_t)llround(i * 1e9 / rate);
        s.gyro_radps = hl_v3(0.01 * i, 0.5, -0.02);
        s.accel_mps2 = hl_v3(0.1, 9.80665, 0.2);
        s.has_gyro = s.has_accel = 1;
        double a = 0.002 * i;
        s.orientation = (hl_quatd){cos(a), 0, sin(a), 0};
        s.has_orientation = kind == TRK_DEVICE_HDK;
        if (kind <= TRK_DEVICE_RIFT_CV1) {
            s.mag_gauss = hl_v3(0.2, -0.4, 0.1);
            s.has_mag = 1;
        }
        uint8_t r[64];
        int len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
        if (len < 0) {
            fprintf(stderr, "encoder: %s\n", err.msg);
            return -1;
        }
        if (len > 0) {
            memcpy(reports[count], r, (size_t)len);
            lengths[count] = (size_t)len;
            times_ns[count] = s.device_time_ns;
            ++count;
        }
    }
    return count;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_make_seeds CORPUS_DIR\n");
        return 1;
    }
    const char *dir = argv[1];
    static const struct {
        enum trk_device_kind kind;
        const char *name;
    } kinds[] = {{TRK_DEVICE_RIFT_DK1, "dk1"}, {TRK_DEVICE_RIFT_DK2, "dk2"}, {TRK_DEVICE_RIFT_CV1, "cv1"},
                 {TRK_DEVICE_PSVR, "psvr"},    {TRK_DEVICE_VIVE, "vive"},    {TRK_DEVICE_VIVE_PRO_INDEX, "vive-pro"},
                 {TRK_DEVICE_HDK, "hdk"}};
    int rc = 0;
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
        for (int wrap = 0; wrap < 2; ++wrap) {
            uint8_t reports[MAX_REPORTS][64];
            size_t lengths[MAX_REPORTS];
            int64_t times[MAX_REPORTS];
            /* the second seed starts a few ticks before a 16-bit (DK1) / 24-bit / 32-bit wrap */
            int64_t offset = wrap ? (kinds[k].kind == TRK_DEVICE_RIFT_DK1 ? 65530 : kinds[k].kind == TRK_DEVICE_PSVR ? 16777200 : 4294967200LL) : 0;
            int n = make_reports(kinds[k].kind, offset, reports, lengths, times);
            if (n <= 0)
                return 1;
            char name[64];
            snprintf(name, sizeof name, "%s%s", kinds[k].name, wrap ? "-wrap" : "");
            /* report_*: [selector] then [len][report]… (HDK: [i32 µs step][len][report]…) */
            struct seed rep = {.n = 0};
            enum trk_device_kind kd = kinds[k].kind;
            const char *target = kd <= TRK_DEVICE_RIFT_CV1 ? "report_rift" : kd == TRK_DEVICE_PSVR ? "report_psvr"
                                 : kd == TRK_DEVICE_HDK ? "report_hdk" : "report_vive";
            if (kd <= TRK_DEVICE_RIFT_CV1)
                put_le(&rep, kd != TRK_DEVICE_RIFT_DK1, 1);
            else if (kd == TRK_DEVICE_VIVE || kd == TRK_DEVICE_VIVE_PRO_INDEX)
                put_le(&rep, kd == TRK_DEVICE_VIVE ? TRK_VIVE_MODEL_VIVE : TRK_VIVE_MODEL_PRO, 1);
            struct seed st = {.n = 0}, raw = {.n = 0}, fix = {.n = 0};
            put_le(&st, (uint64_t)kd, 1);
            /* recording_repair: kind, vid, pid, host start, wall start, name length, name, then records */
            put_le(&fix, (uint64_t)kd, 1);
            put_le(&fix, 0x2833, 2);
            put_le(&fix, 0x0021, 2);
            put_le(&fix, 5000000000ULL, 8);
            put_le(&fix, 1700000000000000000ULL, 8);
            put_le(&fix, strlen(kinds[k].name), 1);
            put(&fix, kinds[k].name, strlen(kinds[k].name));
            for (int i = 0; i < n; ++i) {
                uint32_t step_us = i ? (uint32_t)((times[i] - times[i - 1]) / 1000) : 1000;
                if (kd == TRK_DEVICE_HDK)
                    put_le(&rep, step_us, 4);
                put_le(&rep, lengths[i], 1);
                put(&rep, reports[i], lengths[i]);
                put_le(&st, step_us, 4);
                put_le(&st, lengths[i], 1);
                put(&st, reports[i], lengths[i]);
                put_le(&fix, lengths[i] == 64 ? 0 : lengths[i], 1);
                put_le(&fix, (uint64_t)(5000000000LL + times[i]), 8);
                put(&fix, reports[i], lengths[i]);
            }
            if ((kd != TRK_DEVICE_RIFT_CV1 || !wrap) && save(dir, target, name, &rep) != 0)
                rc = 1;
            if (save(dir, "stream", name, &st) != 0 || save(dir, "recording_repair", name, &fix) != 0)
                rc = 1;
            /* recording: a real file from the writer */
            if (!wrap) {
                char path[4096];
                snprintf(path, sizeof path, "%s/recording/%s.hmdlraw", dir, kinds[k].name);
                struct hl_error err;
                struct trk_recording *w = trk_recording_create(path, kd, 0x2833, 0x0021, kinds[k].name, &err);
                if (!w) {
                    fprintf(stderr, "%s\n", err.msg);
                    return 1;
                }
                for (int i = 0; i < n; ++i)
                    trk_recording_append(w, 5000000000LL + times[i], reports[i], lengths[i], &err);
                if (trk_recording_close(w, 0, &err) != 0)
                    rc = 1;
                (void)raw;
            }
        }
    }
    return rc;
}
