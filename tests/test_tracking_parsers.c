/* Tracker report parsers (tracking/report_*.c): hand-checked reports per device, encoder round
 * trips, counter wraps, repeats, backward samples, loss, truncation and random bytes. Facts from
 * DEVICES.md §2. */
#include "tests/test_util.h"
#include "tracking/report_internal.h" /* trk_ns_to_counter, the encoders' tick conversion */
#include "tracking/tracking.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define G 9.80665

static struct hl_error err;

/* Deterministic generator (xorshift64*), so failures reproduce. */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rng(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545F4914F6CDD1Dull;
}
static double rng_uniform(double lo, double hi) { return lo + (hi - lo) * (double)(rng() >> 11) / 9007199254740992.0; }

static struct trk_imu_sample make_sample(int64_t t_ns, hl_vec3d gyro, hl_vec3d accel)
{
    struct trk_imu_sample s;
    memset(&s, 0, sizeof s);
    s.device_time_ns = t_ns;
    s.gyro_radps = gyro;
    s.accel_mps2 = accel;
    s.orientation = hl_q_identity();
    s.has_gyro = s.has_accel = 1;
    return s;
}

static void check_vec(hl_vec3d a, hl_vec3d b, double tol, int line)
{
    if (!(fabs(a.x - b.x) <= tol && fabs(a.y - b.y) <= tol && fabs(a.z - b.z) <= tol)) {
        ++tu_failures;
        fprintf(stderr, "%s:%d: (%.9g %.9g %.9g) vs (%.9g %.9g %.9g) ± %.3g\n", __FILE__, line, a.x, a.y, a.z, b.x, b.y,
                b.z, tol);
    }
    ++tu_checks;
}
#define CHECK_VEC(a, b, tol) check_vec((a), (b), (tol), __LINE__)

static int counters_consistent(const struct trk_report_counters *n, uint64_t calls, uint64_t emitted)
{
    return n->reports + n->rejected == calls && n->samples == emitted;
}

/* ---- shared helpers ----------------------------------------------------------------------------- */

static void test_21bit(void)
{
    /* Bit strings worked out by hand: x | y | z, 21 bits each, big-endian, last bit 0. */
    static const uint8_t a[8] = {0xFF, 0xFF, 0xF8, 0x00, 0x00, 0x60, 0x00, 0x00}; /* −1, 1, −2^20 */
    static const uint8_t b[8] = {0x00, 0x1F, 0x47, 0xFF, 0xFF, 0x9F, 0xFF, 0xFE}; /* 1000, −2, 2^20−1 */
    int32_t v[3];
    trk_unpack_21bit_triple(a, v);
    CHECK(v[0] == -1 && v[1] == 1 && v[2] == -1048576);
    trk_unpack_21bit_triple(b, v);
    CHECK(v[0] == 1000 && v[1] == -2 && v[2] == 1048575);
    uint8_t out[8];
    int32_t in[3] = {1000, -2, 1048575};
    trk_pack_21bit_triple(in, out);
    CHECK(memcmp(out, b, 8) == 0);
    int32_t clamp[3] = {5000000, -5000000, 0};
    trk_pack_21bit_triple(clamp, out);
    trk_unpack_21bit_triple(out, v);
    CHECK(v[0] == 1048575 && v[1] == -1048576 && v[2] == 0);
    for (int i = 0; i < 10000; ++i) {
        int32_t r[3], back[3];
        for (int k = 0; k < 3; ++k)
            r[k] = (int32_t)(rng() % 0x200000) - 0x100000;
        trk_pack_21bit_triple(r, out);
        trk_unpack_21bit_triple(out, back);
        CHECK(back[0] == r[0] && back[1] == r[1] && back[2] == r[2]);
    }
}

static void test_tick_clock(void)
{
    /* Every width: a wrap forward is a step, a step back of ≤ half the range is backward. */
    static const uint32_t widths[] = {8, 12, 16, 24, 31, 32};
    for (size_t w = 0; w < sizeof widths / sizeof widths[0]; ++w) {
        uint32_t bits = widths[w];
        uint64_t range = 1ull << bits;
        uint32_t mask = (uint32_t)(range - 1);
        struct trk_tick_clock c;
        trk_tick_clock_init(&c, bits, 1000, 1);
        int64_t t0, t;
        uint32_t start = (uint32_t)(range - 3);
        CHECK(trk_tick_clock_unwrap(&c, start, &t0) == 1 && t0 == (int64_t)start);
        CHECK(trk_tick_clock_unwrap(&c, (start + 5) & mask, &t) == 1 && t == t0 + 5); /* across the wrap */
        CHECK(trk_tick_clock_unwrap(&c, (start + 5) & mask, &t) == 0 && t == t0 + 5);
        CHECK(trk_tick_clock_unwrap(&c, (start + 4) & mask, &t) == -1);              /* one back */
        CHECK(trk_tick_clock_unwrap(&c, start, &t) == -1);                           /* back over the wrap */
        /* Exactly half the range is ambiguous: treated as backward (never a jump into the future). */
        CHECK(trk_tick_clock_unwrap(&c, (uint32_t)((start + 5 + range / 2) & mask), &t) == -1);
        CHECK(trk_tick_clock_unwrap(&c, (uint32_t)((start + 4 + range / 2) & mask), &t) == 1 &&
              t == t0 + 4 + (int64_t)(range / 2));
        CHECK(trk_tick_clock_ns(&c, t) == t * 1000);
        /* Many wraps in steps of a third of the range stay monotonic and exact. */
        int64_t expect = t;
        uint32_t raw = (uint32_t)((start + 4 + range / 2) & mask);
        for (int i = 0; i < 20; ++i) {
            raw = (uint32_t)((raw + range / 3) & mask);
            expect += (int64_t)(range / 3);
            CHECK(trk_tick_clock_unwrap(&c, raw, &t) == 1 && t == expect);
        }
    }
    /* The Vive period is 125/6 ns: 48 000 000 ticks are exactly one second. */
    struct trk_tick_clock v;
    trk_tick_clock_init(&v, 32, 125, 6);
    CHECK(trk_tick_clock_ns(&v, 48000000) == 1000000000);
    CHECK(trk_tick_clock_ns(&v, 48) == 1000);
}

/* ---- Rift ---------------------------------------------------------------------------------------- */

static void test_rift_hand(void)
{
    uint8_t r[62];
    memset(r, 0, sizeof r);
    r[0] = 0x01;
    r[1] = 2;            /* two new samples */
    r[2] = 0x34;         /* timestamp 0x1234 ms */
    r[3] = 0x12;
    static const uint8_t a[8] = {0xFF, 0xFF, 0xF8, 0x00, 0x00, 0x60, 0x00, 0x00}; /* −1, 1, −2^20 */
    static const uint8_t b[8] = {0x0B, 0xF8, 0x97, 0xF3, 0xF1, 0xC0, 0x00, 0x00}; /* 98066, −12345, 0 */
    memcpy(r + 8, a, 8);      /* slot 0 accel */
    memcpy(r + 16, b, 8);     /* slot 0 gyro */
    memcpy(r + 24, b, 8);     /* slot 1 accel */
    memcpy(r + 32, a, 8);     /* slot 1 gyro */
    memcpy(r + 40, a, 8);     /* slot 2: not valid with N = 2 */
    /* Magnetometer [56..61], little-endian i16: −1234, 2500, −32768 → −0.1234, 0.25, −3.2768 gauss. */
    static const uint8_t mag1[6] = {0x2E, 0xFB, 0xC4, 0x09, 0x00, 0x80};
    memcpy(r + 56, mag1, 6);
    struct trk_rift_parser p;
    trk_rift_parser_init(&p, 0);
    struct trk_imu_sample s[TRK_REPORT_MAX_SAMPLES];
    CHECK(trk_rift_parse(&p, r, sizeof r, s, TRK_REPORT_MAX_SAMPLES, &err) == 2);
    CHECK(s[0].device_time_ns == 4659000000ll && s[1].device_time_ns == 4660000000ll);
    CHECK_VEC(s[0].accel_mps2, hl_v3(-1e-4, 1e-4, -104.8576), 1e-12);
    CHECK_VEC(s[0].gyro_radps, hl_v3(9.8066, -1.2345, 0), 1e-12);
    CHECK_VEC(s[1].accel_mps2, hl_v3(9.8066, -1.2345, 0), 1e-12);
    CHECK_VEC(s[1].gyro_radps, hl_v3(-1e-4, 1e-4, -104.8576), 1e-12);
    CHECK(s[0].has_gyro && s[0].has_accel && !s[0].has_orientation);
    /* One reading per report, on the newest sample only. */
    CHECK(!s[0].has_mag && s[1].has_mag);
    CHECK_VEC(s[1].mag_gauss, hl_v3(-0.1234, 0.25, -3.2768), 1e-12);
    /* Padded 64-byte variant is accepted; the same timestamp again is a duplicate. */
    uint8_t r64[64];
    memset(r64, 0, sizeof r64);
    memcpy(r64, r, sizeof r);
    CHECK(trk_rift_parse(&p, r64, sizeof r64, s, 3, &err) == 0);
    CHECK(p.n.duplicates == 2 && p.n.reports == 2);

    /* DK2/CV1: N = 1, µs timestamp 0x12345678, one slot. */
    uint8_t d[64];
    memset(d, 0, sizeof d);
    d[0] = 0x0B;
    d[3] = 1;
    d[8] = 0x78; d[9] = 0x56; d[10] = 0x34; d[11] = 0x12;
    memcpy(d + 12, b, 8);
    memcpy(d + 20, a, 8);
    struct trk_rift_parser q;
    trk_rift_parser_init(&q, 1);
    CHECK(trk_rift_parse(&q, d, sizeof d, s, 3, &err) == 1);
    CHECK(s[0].device_time_ns == 0x12345678ll * 1000);
    CHECK(!s[0].has_mag); /* [44..49] all zero: no reading */
    /* DK2 magnetometer [44..49]: −4800, 1, −1 → −0.48, 0.0001, −0.0001 gauss. */
    static const uint8_t mag2[6] = {0x40, 0xED, 0x01, 0x00, 0xFF, 0xFF};
    memcpy(d + 44, mag2, 6);
    d[8] = 0x79; /* 1 µs later: a new sample */
    CHECK(trk_rift_parse(&q, d, sizeof d, s, 3, &err) == 1);
    CHECK(s[0].has_mag);
    CHECK_VEC(s[0].mag_gauss, hl_v3(-0.48, 1e-4, -1e-4), 1e-12);
    d[8] = 0x78;
    CHECK_VEC(s[0].accel_mps2, hl_v3(9.8066, -1.2345, 0), 1e-12);
    CHECK_VEC(s[0].gyro_radps, hl_v3(-1e-4, 1e-4, -104.8576), 1e-12);
    /* N = 5 on a DK2: 3 lost, two slots delivered 1 ms apart. */
    d[3] = 5;
    d[8] = 0x60; d[9] = 0x5E; d[10] = 0x34; d[11] = 0x12; /* +0xE8 (232 ms... in µs: 0x5E60 − 0x5678 = 2024 µs) */
    CHECK(trk_rift_parse(&q, d, sizeof d, s, 3, &err) == 2);
    CHECK(q.n.lost == 3);
    CHECK(s[1].device_time_ns - s[0].device_time_ns == 1000000);
    CHECK(s[1].device_time_ns == 0x12345E60ll * 1000);
    /* Wrong parser for the report: the ID check says so. */
    CHECK(trk_rift_parse(&p, d, sizeof d, s, 3, &err) == -1 && strstr(err.msg, "report id") != NULL);
}

/* ---- PSVR ---------------------------------------------------------------------------------------- */

static void put16(uint8_t *p, int v) { p[0] = (uint8_t)(v & 0xFF); p[1] = (uint8_t)((v >> 8) & 0xFF); }

static void test_psvr_hand(void)
{
    uint8_t r[64];
    memset(r, 0, sizeof r);
    /* Sample 0: tick 0xABCDEF with garbage in the unused top byte. */
    r[16] = 0xEF; r[17] = 0xCD; r[18] = 0xAB; r[19] = 0x7F;
    put16(r + 20, 100); put16(r + 22, -200); put16(r + 24, 300);     /* gyro w0 w1 w2 */
    put16(r + 26, 16384); put16(r + 28, 0); put16(r + 30, -16384);   /* accel w0 w1 w2 */
    /* Sample 1: 500 µs later. */
    uint32_t t1 = 0xABCDEF + 500;
    r[32] = (uint8_t)t1; r[33] = (uint8_t)(t1 >> 8); r[34] = (uint8_t)(t1 >> 16);
    put16(r + 36, -1); put16(r + 38, 2); put16(r + 40, -3);
    put16(r + 42, 0); put16(r + 44, -8192); put16(r + 46, 0);
    struct trk_psvr_parser p;
    trk_psvr_parser_init(&p);
    struct trk_imu_sample s[3];
    CHECK(trk_psvr_parse(&p, r, sizeof r, s, 3, &err) == 2);
    CHECK(s[0].device_time_ns == 0xABCDEFll * 1000);
    CHECK(s[1].device_time_ns - s[0].device_time_ns == 500000);
    /* x = w1, y = w0, z = −w2 */
    CHECK_VEC(s[0].gyro_radps, hl_v3(-200 * 0.00105, 100 * 0.00105, -300 * 0.00105), 1e-12);
    CHECK_VEC(s[0].accel_mps2, hl_v3(0, G, G), 1e-12);
    CHECK_VEC(s[1].gyro_radps, hl_v3(2 * 0.00105, -1 * 0.00105, 3 * 0.00105), 1e-12);
    CHECK_VEC(s[1].accel_mps2, hl_v3(-G / 2, 0, 0), 1e-12);
    /* The same report again: sample 1 repeats the last time, sample 0 is behind it. */
    CHECK(trk_psvr_parse(&p, r, sizeof r, s, 3, &err) == 0 && p.n.duplicates == 1 && p.n.backward == 1);
}

/* ---- Vive ----------------------------------------------------------------------------------------- */

static void vive_slot(uint8_t *r, int slot, int ax, int ay, int az, int gx, int gy, int gz, uint32_t t, uint8_t seq)
{
    uint8_t *s = r + 1 + 17 * slot;
    put16(s, ax); put16(s + 2, ay); put16(s + 4, az);
    put16(s + 6, gx); put16(s + 8, gy); put16(s + 10, gz);
    s[12] = (uint8_t)t; s[13] = (uint8_t)(t >> 8); s[14] = (uint8_t)(t >> 16); s[15] = (uint8_t)(t >> 24);
    s[16] = seq;
}

static void test_vive_hand(void)
{
    uint8_t r[52];
    memset(r, 0, sizeof r);
    r[0] = 0x20;
    /* Slots out of order: seq 10, 8, 9 — emitted 8, 9, 10. 48 000 ticks = 1 ms. */
    vive_slot(r, 0, 0, 8192, 0, 0, 0, 32767, 1000000 + 96000, 10);
    vive_slot(r, 1, 8192, 0, 0, 16384, 0, 0, 1000000, 8);
    vive_slot(r, 2, 0, 0, -8192, 0, -16384, 0, 1000000 + 48000, 9);
    struct trk_vive_parser p;
    trk_vive_parser_init(&p, TRK_VIVE_MODEL_VIVE);
    struct trk_imu_sample s[3];
    CHECK(trk_vive_parse(&p, r, sizeof r, s, 3, &err) == 3);
    CHECK(s[1].device_time_ns - s[0].device_time_ns == 1000000 && s[2].device_time_ns - s[1].device_time_ns == 1000000);
    CHECK(s[0].device_time_ns == (1000000ll * 125) / 6 + 0); /* 20 833 333.3 ns rounds down */
    double a = 39.2266 / 4, g = 8.726646;
    /* Vive: body = (x, −y, −z) of the device */
    CHECK_VEC(s[0].accel_mps2, hl_v3(a, 0, 0), 1e-12);
    CHECK_VEC(s[0].gyro_radps, hl_v3(g / 2, 0, 0), 1e-12);
    CHECK_VEC(s[1].accel_mps2, hl_v3(0, 0, a), 1e-12);
    CHECK_VEC(s[1].gyro_radps, hl_v3(0, g / 2, 0), 1e-12);
    CHECK_VEC(s[2].accel_mps2, hl_v3(0, -a, 0), 1e-12);
    CHECK_VEC(s[2].gyro_radps, hl_v3(0, 0, -g * 32767 / 32768), 1e-12);
    CHECK(p.n.duplicates == 0 && p.n.lost == 0);
    /* Next ring: 11 replaces 8; 9 and 10 are repeats. */
    vive_slot(r, 1, 0, 0, 0, 0, 0, 0, 1000000 + 144000, 11);
    CHECK(trk_vive_parse(&p, r, sizeof r, s, 3, &err) == 1 && p.n.duplicates == 2);
    CHECK(s[0].device_time_ns == (int64_t)((1144000ll * 125 + 3) / 6));
    /* Seqs 12..13 never arrive: ring 14, 15, 16 ⇒ 2 lost. */
    vive_slot(r, 0, 0, 0, 0, 0, 0, 0, 1000000 + 6 * 48000, 14);
    vive_slot(r, 1, 0, 0, 0, 0, 0, 0, 1000000 + 7 * 48000, 15);
    vive_slot(r, 2, 0, 0, 0, 0, 0, 0, 1000000 + 8 * 48000, 16);
    CHECK(trk_vive_parse(&p, r, sizeof r, s, 3, &err) == 3 && p.n.lost == 2);
    /* Ranges from feature 0x01 modes: n = 2 → 1000 °/s and 8 g. */
    CHECK(trk_vive_set_range_modes(&p.cal, 2, 2, &err) == 0);
    CHECK_NEAR(p.cal.gyro_range_radps, 1000 * HL_PI / 180, 1e-12);
    CHECK_NEAR(p.cal.accel_range_mps2, 8 * G, 1e-12);
    CHECK(trk_vive_set_range_modes(&p.cal, 5, 0, &err) == -1 && err.msg[0]);
    /* Index axes: x' = −y, y' = −x, z' = −z. */
    struct trk_vive_parser ix;
    trk_vive_parser_init(&ix, TRK_VIVE_MODEL_INDEX);
    vive_slot(r, 0, 8192, 0, 0, 0, 0, 0, 5000, 1);
    vive_slot(r, 1, 0, 8192, 0, 0, 0, 0, 5000 + 48000, 2);
    vive_slot(r, 2, 0, 0, 8192, 0, 0, 0, 5000 + 96000, 3);
    CHECK(trk_vive_parse(&ix, r, sizeof r, s, 3, &err) == 3);
    CHECK_VEC(s[0].accel_mps2, hl_v3(0, -a, 0), 1e-12);
    CHECK_VEC(s[1].accel_mps2, hl_v3(-a, 0, 0), 1e-12);
    CHECK_VEC(s[2].accel_mps2, hl_v3(0, 0, -a), 1e-12);
}

/* ---- HDK ------------------------------------------------------------------------------------------ */

static void test_hdk_hand(void)
{
    uint8_t r[32];
    memset(r, 0, sizeof r);
    r[0] = 0x12; /* version 2 (status nibble ignored below v3) */
    r[1] = 5;
    put16(r + 2, 0); put16(r + 4, 0); put16(r + 6, 11585); put16(r + 8, 11585); /* 90° about device z */
    put16(r + 10, 512); put16(r + 12, 0); put16(r + 14, -1024);               /* (1, 0, −2) rad/s */
    struct trk_hdk_parser p;
    trk_hdk_parser_init(&p);
    struct trk_imu_sample s[3];
    CHECK(trk_hdk_parse(&p, r, 32, 123456789, s, 3, &err) == 1);
    CHECK(s[0].device_time_ns == 123456789 && s[0].has_orientation && s[0].has_gyro && !s[0].has_accel);
    /* body = (x, z, −y) of the device: device z is body +Y */
    CHECK_NEAR(s[0].orientation.w, sqrt(0.5), 1e-4);
    CHECK_NEAR(s[0].orientation.y, sqrt(0.5), 1e-4);
    CHECK_NEAR(s[0].orientation.x, 0, 1e-12);
    CHECK_NEAR(s[0].orientation.z, 0, 1e-12);
    CHECK_NEAR(hl_q_norm(s[0].orientation), 1, 1e-12);
    CHECK_VEC(s[0].gyro_radps, hl_v3(1, -2, 0), 1e-12);
    /* Repeat of seq 5 is a duplicate; seq 8 means 6 and 7 were lost; v1 has no gyro. */
    CHECK(trk_hdk_parse(&p, r, 32, 123456790, s, 3, &err) == 0 && p.n.duplicates == 1);
    r[0] = 0x01;
    r[1] = 8;
    CHECK(trk_hdk_parse(&p, r, 16, 123456791, s, 3, &err) == 1 && p.n.lost == 2 && !s[0].has_gyro);
    /* Host time going back: dropped as backward. */
    r[1] = 9;
    CHECK(trk_hdk_parse(&p, r, 16, 100, s, 3, &err) == 0 && p.n.backward == 1);
    /* A zero quaternion is no rotation. */
    memset(r + 2, 0, 8);
    r[1] = 10;
    CHECK(trk_hdk_parse(&p, r, 16, 123456800, s, 3, &err) == -1 && strstr(err.msg, "quaternion") != NULL);
    r[0] = 0x00;
    CHECK(trk_hdk_parse(&p, r, 16, 123456800, s, 3, &err) == -1 && strstr(err.msg, "version") != NULL);
}

/* ---- encoder round trips, wraps, repeats, loss --------------------------------------------------- */

struct dev {
    const char *name;
    enum trk_device_kind kind;
    int64_t period_num, period_den; /* device tick in ns */
    uint32_t bits;
    double gyro_lsb, accel_lsb, gyro_max, accel_max;
    int64_t dt_ns; /* native sample spacing */
};

static const struct dev devices[] = {
    {"rift dk1", TRK_DEVICE_RIFT_DK1, 1000000, 1, 16, 1e-4, 1e-4, 100, 100, 1000000},
    {"rift dk2", TRK_DEVICE_RIFT_DK2, 1000, 1, 32, 1e-4, 1e-4, 100, 100, 1000000},
    {"rift cv1", TRK_DEVICE_RIFT_CV1, 1000, 1, 32, 1e-4, 1e-4, 100, 100, 1000000},
    {"psvr", TRK_DEVICE_PSVR, 1000, 1, 24, 0.00105, G / 16384, 30, 19, 500000},
    {"vive", TRK_DEVICE_VIVE, 125, 6, 32, 8.726646 / 32768, 39.2266 / 32768, 8.7, 39, 1000000},
    {"vive pro", TRK_DEVICE_VIVE_PRO_INDEX, 125, 6, 32, 8.726646 / 32768, 39.2266 / 32768, 8.7, 39, 1000000},
    {"hdk", TRK_DEVICE_HDK, 1, 1, 0, 1.0 / 512, 0, 60, 0, 2500000},
};
#define NDEV ((int)(sizeof devices / sizeof devices[0]))

/* One parser of any kind behind one call. */
struct any_parser {
    enum trk_device_kind kind;
    struct trk_rift_parser rift;
    struct trk_psvr_parser psvr;
    struct trk_vive_parser vive;
    struct trk_hdk_parser hdk;
    int64_t host_ns;
};

static void any_init(struct any_parser *a, enum trk_device_kind kind)
{
    memset(a, 0, sizeof *a);
    a->kind = kind;
    trk_rift_parser_init(&a->rift, kind != TRK_DEVICE_RIFT_DK1);
    trk_psvr_parser_init(&a->psvr);
    trk_vive_parser_init(&a->vive, kind == TRK_DEVICE_VIVE_PRO_INDEX ? TRK_VIVE_MODEL_PRO : TRK_VIVE_MODEL_VIVE);
    trk_hdk_parser_init(&a->hdk);
}

static int any_parse(struct any_parser *a, const uint8_t *r, size_t len, int64_t host_ns, struct trk_imu_sample *out)
{
    switch (a->kind) {
    case TRK_DEVICE_RIFT_DK1:
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1: return trk_rift_parse(&a->rift, r, len, out, TRK_REPORT_MAX_SAMPLES, &err);
    case TRK_DEVICE_PSVR: return trk_psvr_parse(&a->psvr, r, len, out, TRK_REPORT_MAX_SAMPLES, &err);
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: return trk_vive_parse(&a->vive, r, len, out, TRK_REPORT_MAX_SAMPLES, &err);
    case TRK_DEVICE_HDK:
    default: return trk_hdk_parse(&a->hdk, r, len, host_ns, out, TRK_REPORT_MAX_SAMPLES, &err);
    }
}

static const struct trk_report_counters *any_counters(const struct any_parser *a)
{
    switch (a->kind) {
    case TRK_DEVICE_PSVR: return &a->psvr.n;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: return &a->vive.n;
    case TRK_DEVICE_HDK: return &a->hdk.n;
    default: return &a->rift.n;
    }
}

static struct trk_imu_sample random_sample(const struct dev *d, int64_t t_ns)
{
    struct trk_imu_sample s = make_sample(t_ns, hl_v3(rng_uniform(-d->gyro_max, d->gyro_max), rng_uniform(-d->gyro_max, d->gyro_max),
                                                      rng_uniform(-d->gyro_max, d->gyro_max)),
                                          hl_v3(rng_uniform(-d->accel_max, d->accel_max), rng_uniform(-d->accel_max, d->accel_max),
                                                rng_uniform(-d->accel_max, d->accel_max)));
    if (d->kind == TRK_DEVICE_HDK) {
        s.orientation = hl_q_normalize(hl_q(rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1)));
        s.has_accel = 0;
        s.has_orientation = 1;
    }
    if (d->kind == TRK_DEVICE_RIFT_DK1 || d->kind == TRK_DEVICE_RIFT_DK2 || d->kind == TRK_DEVICE_RIFT_CV1) {
        /* ±3 gauss of the ±3.2767 range; 0.5 gauss on x keeps the triple off all-zero ("none"). */
        s.mag_gauss = hl_v3(0.5 + rng_uniform(-2.5, 2.5), rng_uniform(-3, 3), rng_uniform(-3, 3));
        s.has_mag = 1;
    }
    return s;
}

/* Streams `count` samples through the device simulator and the parser; checks values within one
 * LSB, the spacing of consecutive times (across any wrap) and the counters. */
static void round_trip(const struct dev *d, const struct trk_encoder_options *opt, int count, uint64_t expect_dup_per_report)
{
    struct trk_encoder enc;
    trk_encoder_init(&enc, d->kind, opt);
    struct any_parser a;
    any_init(&a, d->kind);
    static struct trk_imu_sample sent[4096];
    int sent_n = 0, got = 0, bad_values = 0, bad_dt = 0;
    int64_t t0 = 1000000000, prev_parsed = 0;
    uint64_t calls = 0, reports = 0;
    for (int i = 0; i < count; ++i) {
        struct trk_imu_sample s = random_sample(d, t0 + (int64_t)i * d->dt_ns);
        sent[sent_n++ % 4096] = s;
        uint8_t r[64];
        int len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
        CHECK(len >= 0);
        if (len <= 0)
            continue;
        ++reports;
        struct trk_imu_sample out[TRK_REPORT_MAX_SAMPLES];
        ++calls;
        int n = any_parse(&a, r, (size_t)len, s.device_time_ns, out);
        if (n < 0) {
            fprintf(stderr, "%s: %s\n", d->name, err.msg);
            CHECK(n >= 0);
            continue;
        }
        for (int k = 0; k < n; ++k) {
            /* With no loss the k-th parsed sample matches the k-th sent one. */
            const struct trk_imu_sample *e = &sent[got % 4096];
            if (!opt || (!opt->drop_report_every && opt->samples_per_report <= 1) || d->kind == TRK_DEVICE_PSVR) {
                double gt = d->gyro_lsb * 0.5000001, at = d->accel_lsb * 0.5000001;
                if (fabs(out[k].gyro_radps.x - e->gyro_radps.x) > gt || fabs(out[k].gyro_radps.y - e->gyro_radps.y) > gt ||
                    fabs(out[k].gyro_radps.z - e->gyro_radps.z) > gt)
                    ++bad_values;
                if (d->kind == TRK_DEVICE_HDK) {
                    if (hl_q_angle_rad(out[k].orientation, e->orientation) > 4.0 / 16384)
                        ++bad_values;
                } else if (fabs(out[k].accel_mps2.x - e->accel_mps2.x) > at || fabs(out[k].accel_mps2.y - e->accel_mps2.y) > at ||
                           fabs(out[k].accel_mps2.z - e->accel_mps2.z) > at) {
                    ++bad_values;
                }
                /* Rift magnetometer: one per report, on its newest sample, within half an LSB. */
                if (e->has_mag != out[k].has_mag ||
                    (e->has_mag && (fabs(out[k].mag_gauss.x - e->mag_gauss.x) > 0.5000001e-4 ||
                                    fabs(out[k].mag_gauss.y - e->mag_gauss.y) > 0.5000001e-4 ||
                                    fabs(out[k].mag_gauss.z - e->mag_gauss.z) > 0.5000001e-4)))
                    ++bad_values;
                if (got > 0 && d->kind != TRK_DEVICE_HDK) {
                    int64_t dt = out[k].device_time_ns - prev_parsed;
                    int64_t tick = (d->period_num + d->period_den - 1) / d->period_den;
                    if (llabs(dt - d->dt_ns) > tick)
                        ++bad_dt;
                }
            }
            if (got > 0 && out[k].device_time_ns <= prev_parsed)
                ++bad_dt;
            prev_parsed = out[k].device_time_ns;
            ++got;
        }
    }
    const struct trk_report_counters *c = any_counters(&a);
    CHECK(bad_values == 0);
    CHECK(bad_dt == 0);
    CHECK(counters_consistent(c, calls, (uint64_t)got));
    CHECK(c->backward == 0);
    if (bad_values || bad_dt)
        fprintf(stderr, "%s: %d bad values, %d bad dt of %d samples\n", d->name, bad_values, bad_dt, got);
    if (!opt || (!opt->drop_report_every && opt->samples_per_report <= 1)) {
        CHECK(got == count - (d->kind == TRK_DEVICE_PSVR ? count % 2 : 0));
        CHECK(c->lost == 0);
        /* Vive: every report after the first repeats the two samples before it. */
        if (expect_dup_per_report)
            CHECK(c->duplicates == expect_dup_per_report * reports);
        else
            CHECK(c->duplicates == 0);
    }
}

static void test_round_trips(void)
{
    for (int i = 0; i < NDEV; ++i) {
        const struct dev *d = &devices[i];
        int vive = d->kind == TRK_DEVICE_VIVE || d->kind == TRK_DEVICE_VIVE_PRO_INDEX;
        round_trip(d, NULL, 3000, vive ? 2 : 0); /* Vive ring: first report has 2 in-ring repeats too */
    }
}

static void test_wraps(void)
{
    /* Start each counter 40 samples before its wrap and stream 3000 samples across it. */
    for (int i = 0; i < NDEV; ++i) {
        const struct dev *d = &devices[i];
        if (d->kind == TRK_DEVICE_HDK)
            continue; /* no device clock */
        struct trk_encoder_options opt;
        memset(&opt, 0, sizeof opt);
        int64_t range = (int64_t)1 << d->bits;
        int64_t ticks_per_sample = d->dt_ns * d->period_den / d->period_num;
        int64_t t0_ticks = 1000000000 * d->period_den / d->period_num; /* round_trip starts at 1 s */
        int64_t off = range - (t0_ticks % range) - 40 * ticks_per_sample;
        off -= ((off % 6) + 6) % 6; /* multiple of 6 keeps the Vive offset exact in ns */
        opt.counter_offset_ticks = off;
        int vive = d->kind == TRK_DEVICE_VIVE || d->kind == TRK_DEVICE_VIVE_PRO_INDEX;
        round_trip(d, &opt, 3000, vive ? 2 : 0);
    }
    /* DK1's 16-bit ms counter wraps every 65.536 s: 200 s of reports wrap it three times. */
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK1, NULL);
    struct trk_rift_parser p;
    trk_rift_parser_init(&p, 0);
    int64_t prev = -1;
    int ok = 1;
    for (int64_t ms = 0; ms < 200000; ++ms) {
        struct trk_imu_sample s = make_sample(ms * 1000000, hl_v3(0, 0, 0), hl_v3(0, G, 0));
        uint8_t r[64];
        int len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
        struct trk_imu_sample out[3];
        int n = trk_rift_parse(&p, r, (size_t)len, out, 3, &err);
        if (n != 1 || (prev >= 0 && out[0].device_time_ns - prev != 1000000))
            ok = 0;
        prev = n == 1 ? out[0].device_time_ns : prev;
    }
    CHECK(ok);
    CHECK(prev == 199999ll * 1000000);
}

static void test_loss_and_backward(void)
{
    struct trk_encoder_options opt;
    /* DK1 batching 5 samples per report: N = 5 ⇒ 2 lost per report, the 3 newest delivered. */
    memset(&opt, 0, sizeof opt);
    opt.samples_per_report = 5;
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK1, &opt);
    struct trk_rift_parser p;
    trk_rift_parser_init(&p, 0);
    int got = 0;
    for (int i = 0; i < 500; ++i) {
        struct trk_imu_sample s = make_sample((int64_t)i * 1000000, hl_v3(i * 1e-3, 0, 0), hl_v3(0, G, 0));
        uint8_t r[64];
        struct trk_imu_sample out[3];
        int len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
        if (len > 0) {
            int n = trk_rift_parse(&p, r, (size_t)len, out, 3, &err);
            CHECK(n == 3);
            if (n == 3) /* the newest three: samples i−2, i−1, i */
                CHECK_NEAR(out[0].gyro_radps.x, (i - 2) * 1e-3, 1e-4);
            got += n > 0 ? n : 0;
        }
    }
    CHECK(p.n.lost == 200 && got == 300 && p.n.reports == 100);
    /* DK2 with 3 per report: 1 lost each. */
    opt.samples_per_report = 3;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, &opt);
    trk_rift_parser_init(&p, 1);
    for (int i = 0; i < 300; ++i) {
        struct trk_imu_sample s = make_sample((int64_t)i * 1000000, hl_v3(0, 0, 0), hl_v3(0, G, 0));
        uint8_t r[64];
        struct trk_imu_sample out[3];
        int len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
        if (len > 0)
            CHECK(trk_rift_parse(&p, r, (size_t)len, out, 3, &err) == 2);
    }
    CHECK(p.n.lost == 100 && p.n.samples == 200);

    /* Vive: every 2nd report withheld. With one sample per report the ring's repeats recover each
     * lost report; with 3 per report a withheld ring loses its 3 samples. */
    for (int spr = 1; spr <= 3; spr += 2) {
        memset(&opt, 0, sizeof opt);
        opt.drop_report_every = 2;
        opt.samples_per_report = spr;
        trk_encoder_init(&enc, TRK_DEVICE_VIVE, &opt);
        struct trk_vive_parser v;
        trk_vive_parser_init(&v, TRK_VIVE_MODEL_VIVE);
        int delivered = 0;
        for (int i = 0; i < 600; ++i) { /* seq wraps past 255 twice */
            struct trk_imu_sample s = make_sample(1000000000 + (int64_t)i * 1000000, hl_v3(0, 0, 0), hl_v3(0, G, 0));
            uint8_t r[64];
            struct trk_imu_sample out[3];
            int len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
            if (len > 0) {
                int n = trk_vive_parse(&v, r, (size_t)len, out, 3, &err);
                CHECK(n >= 0);
                delivered += n > 0 ? n : 0;
            }
        }
        CHECK(v.n.backward == 0);
        /* The last report (every 2nd withheld) never arrives: 1 sample (spr 1) or 3 unseen. */
        CHECK(v.n.samples + v.n.lost == (spr == 1 ? 599u : 597u));
        if (spr == 1)
            CHECK(v.n.lost == 0);
        else
            CHECK(v.n.lost == 300 - 3);
        CHECK((int)v.n.samples == delivered);
    }

    /* Backward reports for every device: a later report, then an earlier one. */
    for (int i = 0; i < NDEV; ++i) {
        const struct dev *d = &devices[i];
        struct trk_encoder e1, e2;
        trk_encoder_init(&e1, d->kind, NULL);
        trk_encoder_init(&e2, d->kind, NULL);
        e2.seq = 5; /* Vive: new seqs, so only the time says it is old */
        struct any_parser a;
        any_init(&a, d->kind);
        uint8_t late[64], early[64];
        int late_len = 0, early_len = 0;
        for (int k = 0; k < 2 && late_len <= 0; ++k) {
            struct trk_imu_sample s = random_sample(d, 2000000000 + k * d->dt_ns);
            late_len = trk_encoder_push(&e1, &s, late, sizeof late, &err);
        }
        for (int k = 0; k < 2 && early_len <= 0; ++k) {
            struct trk_imu_sample s = random_sample(d, 1000000000 + k * d->dt_ns);
            early_len = trk_encoder_push(&e2, &s, early, sizeof early, &err);
        }
        if (d->kind == TRK_DEVICE_HDK)
            early[1] = (uint8_t)(late[1] + 1); /* a new seq, but an earlier host time */
        struct trk_imu_sample out[3];
        int n1 = any_parse(&a, late, (size_t)late_len, 2000000000, out);
        int n2 = any_parse(&a, early, (size_t)early_len, 1000000000, out);
        const struct trk_report_counters *c = any_counters(&a);
        CHECK(n1 >= 1 && n2 == 0);
        CHECK(c->backward >= 1);
        if (n2 != 0 || c->backward < 1)
            fprintf(stderr, "%s: backward report gave %d samples, %llu backward\n", d->name, n2,
                    (unsigned long long)c->backward);
    }
}

/* ---- hostile bytes ---------------------------------------------------------------------------------- */

static void test_truncation_and_ids(void)
{
    for (int i = 0; i < NDEV; ++i) {
        const struct dev *d = &devices[i];
        struct trk_encoder enc;
        trk_encoder_init(&enc, d->kind, NULL);
        uint8_t r[64];
        int len = 0;
        for (int k = 0; k < 2 && len <= 0; ++k) {
            struct trk_imu_sample s = random_sample(d, 1000000000 + k * d->dt_ns);
            len = trk_encoder_push(&enc, &s, r, sizeof r, &err);
        }
        CHECK(len > 0);
        uint8_t buf[80];
        struct trk_imu_sample out[3];
        int all_rejected = 1, all_messages = 1;
        for (int cut = 0; cut < len; ++cut) {
            if (d->kind == TRK_DEVICE_HDK && cut == 16)
                continue; /* the first 16 bytes of a 32-byte HDK report are a valid 16-byte report */
            struct any_parser a;
            any_init(&a, d->kind);
            memcpy(buf, r, (size_t)cut);
            err.msg[0] = 0;
            /* An exact-size buffer, so ASan sees any read past the prefix. */
            uint8_t *exact = cut ? buf : NULL;
            if (any_parse(&a, exact, (size_t)cut, 1, out) != -1)
                all_rejected = 0;
            if (!err.msg[0])
                all_messages = 0;
            if (any_counters(&a)->rejected != 1 || any_counters(&a)->reports != 0)
                all_rejected = 0;
        }
        CHECK(all_rejected);
        CHECK(all_messages);
        /* Wrong IDs (or versions) with the right length. */
        if (d->kind != TRK_DEVICE_PSVR) {
            int wrong_ok = 1;
            for (int id = 0; id < 256; ++id) {
                memcpy(buf, r, (size_t)len);
                buf[0] = (uint8_t)id;
                int valid = d->kind == TRK_DEVICE_HDK ? ((id & 0x0F) >= 1 && (id & 0x0F) <= 3) : id == r[0];
                if (valid)
                    continue;
                struct any_parser a;
                any_init(&a, d->kind);
                err.msg[0] = 0;
                if (any_parse(&a, buf, (size_t)len, 1, out) != -1 || !err.msg[0])
                    wrong_ok = 0;
            }
            CHECK(wrong_ok);
        }
        /* One byte too long is refused too (except DK1's padded 64). */
        if (len < 64 || d->kind != TRK_DEVICE_RIFT_DK1) {
            struct any_parser a;
            any_init(&a, d->kind);
            memcpy(buf, r, (size_t)len);
            buf[len] = 0;
            int n = any_parse(&a, buf, (size_t)len + 1, 1, out);
            CHECK(d->kind == TRK_DEVICE_RIFT_DK1 && len + 1 == 63 ? n == -1 : n == -1);
        }
        /* Too little room for the samples is a caller error, reported the same way. */
        struct trk_rift_parser rp;
        trk_rift_parser_init(&rp, 0);
        uint8_t dk1[62] = {0x01, 1};
        CHECK(trk_rift_parse(&rp, dk1, sizeof dk1, out, 2, &err) == -1 && strstr(err.msg, "room") != NULL);
    }
}

static void test_random_bytes(void)
{
    /* 100k random reports per device, random lengths 0..72; half get the right first byte and
     * length so the deep paths run too. Never a crash; counters add up; times strictly increase. */
    rng_state = 0x1234567887654321ull;
    static const size_t sizes[NDEV] = {62, 64, 64, 64, 52, 52, 32};
    for (int i = 0; i < NDEV; ++i) {
        const struct dev *d = &devices[i];
        struct any_parser a;
        any_init(&a, d->kind);
        uint64_t calls = 0, emitted = 0;
        int64_t prev = INT64_MIN;
        int monotonic = 1, finite = 1, in_range = 1;
        int64_t host = 0;
        for (int k = 0; k < 100000; ++k) {
            uint8_t buf[72];
            size_t len = (size_t)(rng() % 73);
            for (size_t b = 0; b < sizeof buf; ++b)
                buf[b] = (uint8_t)rng();
            if (rng() & 1) {
                len = (d->kind == TRK_DEVICE_HDK && (rng() & 1)) ? 16 : sizes[i];
                if (d->kind == TRK_DEVICE_RIFT_DK1 && (rng() & 1))
                    len = 64;
                if (d->kind == TRK_DEVICE_RIFT_DK1)
                    buf[0] = 0x01;
                else if (d->kind == TRK_DEVICE_RIFT_DK2 || d->kind == TRK_DEVICE_RIFT_CV1)
                    buf[0] = 0x0B;
                else if (d->kind == TRK_DEVICE_VIVE || d->kind == TRK_DEVICE_VIVE_PRO_INDEX)
                    buf[0] = 0x20;
                else if (d->kind == TRK_DEVICE_HDK)
                    buf[0] = (uint8_t)((buf[0] & 0xF0) | (1 + rng() % 3));
            }
            host += (int64_t)(rng() % 5000000) - 1000000; /* mostly forward, sometimes back */
            struct trk_imu_sample out[TRK_REPORT_MAX_SAMPLES];
            ++calls;
            int n = any_parse(&a, buf, len, host, out);
            if (n < -1 || n > TRK_REPORT_MAX_SAMPLES)
                in_range = 0;
            for (int s = 0; s < n; ++s) {
                if (out[s].device_time_ns <= prev)
                    monotonic = 0;
                prev = out[s].device_time_ns;
                if (!isfinite(out[s].gyro_radps.x + out[s].gyro_radps.y + out[s].gyro_radps.z + out[s].accel_mps2.x +
                              out[s].accel_mps2.y + out[s].accel_mps2.z + out[s].orientation.w))
                    finite = 0;
            }
            emitted += n > 0 ? (uint64_t)n : 0;
        }
        const struct trk_report_counters *c = any_counters(&a);
        CHECK(in_range && monotonic && finite);
        CHECK(counters_consistent(c, calls, emitted));
        /* Random Q1.14 quaternions are mostly far from unit norm, so the HDK accepts few. */
        CHECK(c->reports > (d->kind == TRK_DEVICE_HDK ? 1000u : 10000u) && c->rejected > 10000);
        printf("%-9s random: %llu accepted, %llu rejected, %llu samples, %llu lost, %llu dup, %llu back\n", d->name,
               (unsigned long long)c->reports, (unsigned long long)c->rejected, (unsigned long long)c->samples,
               (unsigned long long)c->lost, (unsigned long long)c->duplicates, (unsigned long long)c->backward);
    }
}

/* ---- commands and the device table ------------------------------------------------------------------ */

static void test_builders(void)
{
    uint8_t b[12];
    CHECK(trk_rift_build_keepalive_dk1(b, 0x0102, 10000) == 5);
    CHECK(b[0] == 0x08 && b[1] == 0x02 && b[2] == 0x01 && b[3] == 0x10 && b[4] == 0x27);
    CHECK(trk_rift_build_keepalive_mux(b, 0, 0x0B, 10000) == 6);
    CHECK(b[0] == 0x11 && b[3] == 0x0B && b[4] == 0x10 && b[5] == 0x27);
    CHECK(trk_rift_build_enable_components(b, 7, TRK_RIFT_COMPONENT_DISPLAY | TRK_RIFT_COMPONENT_LEDS) == 4);
    CHECK(b[0] == 0x1D && b[1] == 7 && b[2] == 0 && b[3] == 0x05);
    CHECK(trk_rift_build_config(b, 0, TRK_RIFT_CONFIG_USE_CALIBRATION | TRK_RIFT_CONFIG_AUTO_CALIBRATE, 0, 1000) == 7);
    CHECK(b[0] == 0x02 && b[3] == 0x0C && b[4] == 0 && b[5] == 0xE8 && b[6] == 0x03);
    CHECK(trk_psvr_build_power(b, 1) == 8);
    CHECK(b[0] == 0x17 && b[1] == 0 && b[2] == 0xAA && b[3] == 4 && b[4] == 1 && b[5] == 0);
    CHECK(trk_psvr_build_vr_mode(b, 1) == 8 && b[0] == 0x23 && b[2] == 0xAA && b[4] == 1);
    CHECK(trk_psvr_build_vr_mode(b, 0) == 8 && b[4] == 0);
    CHECK(trk_psvr_build_tracking_on(b) == 12 && b[0] == 0x11 && b[3] == 8 && b[5] == 0xFF && b[8] == 0);

    const struct trk_device_info *d = trk_device_find(0x2833, 0x0031, 0);
    CHECK(d && d->kind == TRK_DEVICE_RIFT_CV1 && d->report_size == 64);
    CHECK(trk_device_find(0x2833, 0x0031, 1) == NULL); /* the CV1 radio */
    d = trk_device_find(0x054c, 0x09af, 4);
    CHECK(d && d->kind == TRK_DEVICE_PSVR && d->role == TRK_ROLE_IMU);
    d = trk_device_find(0x054c, 0x09af, 5);
    CHECK(d && d->role == TRK_ROLE_CONTROL);
    d = trk_device_find(0x2833, 0x0001, 3);
    CHECK(d && d->kind == TRK_DEVICE_RIFT_DK1 && d->manufacturer != NULL);
    d = trk_device_find(0x28de, 0x2000, 0);
    CHECK(d && d->report_size == 52 && d->sample_rate_hz == 1000.0);
    CHECK(trk_device_find(0x1234, 0x5678, 0) == NULL);
    CHECK(trk_device_table_count >= 7);
}

/* Encodes 1 ms samples from t_ns until the encoder emits a report; its length. */
static int encode_report(struct trk_encoder *enc, int64_t *t_ns, uint8_t *r, size_t cap)
{
    for (int i = 0; i < 16; ++i) {
        struct trk_imu_sample smp = make_sample(*t_ns, hl_v3(0, 0, 0), hl_v3(0, G, 0));
        *t_ns += 1000000;
        int len = trk_encoder_push(enc, &smp, r, cap, &err);
        if (len != 0)
            return len;
    }
    return -1;
}

/* The int64-nanosecond edge of every device clock: the unwrapped count reaches exactly the largest
 * value whose time fits, one step more is refused (never wrapped into a negative time), and each
 * parser then refuses the report with an error instead of dropping it silently. */
static void test_counter_extremes(void)
{
    static const struct {
        uint32_t bits, num, den;
    } clocks[] = {{16, 1000000, 1}, {24, 1000, 1}, {32, 1000, 1}, {32, 125, 6}, {2, 1, 1}, {8, 7, 3}};
    for (size_t i = 0; i < sizeof clocks / sizeof clocks[0]; ++i) {
        struct trk_tick_clock c;
        trk_tick_clock_init(&c, clocks[i].bits, clocks[i].num, clocks[i].den);
        int64_t t, max = trk_tick_clock_max_ticks(&c);
        CHECK(max > 0 && (__int128)max * clocks[i].num + clocks[i].den <= (__int128)INT64_MAX);
        CHECK(trk_tick_clock_unwrap(&c, 0, &t) == 1);
        c.ticks = max - 1; /* as if the device had run for ~292 years (DK1) or ~4.9 years (Vive) */
        CHECK(trk_tick_clock_unwrap(&c, 1, &t) == 1 && t == max);
        int64_t ns = trk_tick_clock_ns(&c, t);
        CHECK(ns > 0 && ns != INT64_MAX && (__int128)ns * clocks[i].den >= (__int128)max * clocks[i].num - clocks[i].den);
        CHECK(trk_tick_clock_unwrap(&c, 2, &t) == -2 && c.overflowed && c.ticks == max);
        CHECK(trk_tick_clock_ns(&c, INT64_MAX) == INT64_MAX);
        CHECK(trk_tick_clock_ns(&c, INT64_MIN) == INT64_MIN);
        CHECK(trk_tick_clock_ns(&c, 0) == (int64_t)(clocks[i].den / 2) / (int64_t)clocks[i].den);
    }
    /* Time → counter (the encoders) in 128 bits: 2e18 ns at 125/6 ns is 9.6e16 ticks, mod 2^32. */
    CHECK(trk_ns_to_counter(2000000000000000000LL, 32, 125, 6, 0) == 3396337664u);
    CHECK(trk_ns_to_counter(INT64_MAX, 16, 1000000, 1, 0) == (uint32_t)((INT64_MAX / 1000000 + 1) & 0xFFFF));
    /* floor((−2^63 + 500) / 1000) = −2^63 / 1000 − 1 (C's division truncates; the counter floors) */
    CHECK(trk_ns_to_counter(INT64_MIN, 24, 1000, 1, 0) == (uint32_t)((uint64_t)(INT64_MIN / 1000 - 1) & 0xFFFFFF));

    /* The parsers: one report accepted, then the clock is pushed to its edge and the next refused. */
    const enum trk_device_kind kinds[] = {TRK_DEVICE_RIFT_DK1, TRK_DEVICE_RIFT_DK2, TRK_DEVICE_PSVR, TRK_DEVICE_VIVE};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
        struct trk_encoder enc;
        trk_encoder_init(&enc, kinds[k], NULL);
        struct trk_stream *st = malloc(sizeof *st);
        trk_stream_init(st, kinds[k], NULL);
        struct trk_tick_clock *clk = kinds[k] == TRK_DEVICE_PSVR   ? &st->parser.psvr.clock
                                     : kinds[k] == TRK_DEVICE_VIVE ? &st->parser.vive.clock
                                                                   : &st->parser.rift.clock;
        uint8_t r[64];
        int64_t t_ns = 1000000000;
        int len = encode_report(&enc, &t_ns, r, sizeof r);
        CHECK(len > 0 && trk_stream_feed(st, r, (size_t)len, 0, &err) >= 1);
        clk->ticks = trk_tick_clock_max_ticks(clk);
        len = encode_report(&enc, &t_ns, r, sizeof r);
        memset(&err, 0, sizeof err);
        CHECK(len > 0 && trk_stream_feed(st, r, (size_t)len, 0, &err) == -1 && strstr(err.msg, "int64 nanoseconds"));
        CHECK(st->rejected == 1);
        const struct trk_report_counters *rc = kinds[k] == TRK_DEVICE_PSVR   ? &st->parser.psvr.n
                                               : kinds[k] == TRK_DEVICE_VIVE ? &st->parser.vive.n
                                                                             : &st->parser.rift.n;
        CHECK(rc->rejected == 1 && rc->reports + rc->rejected == 2);
        free(st);
    }
    /* An encoder counter offset whose time does not fit int64 ns is an error, not a wrapped stamp. */
    struct trk_encoder_options opt;
    memset(&opt, 0, sizeof opt);
    opt.counter_offset_ticks = INT64_MAX / 1000;
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK1, &opt);
    struct trk_imu_sample smp = make_sample(0, hl_v3(0, 0, 0), hl_v3(0, G, 0));
    uint8_t r[64];
    CHECK(trk_encoder_push(&enc, &smp, r, sizeof r, &err) == -1 && strstr(err.msg, "does not fit int64"));
}

int main(int argc, char **argv)
{
    /* "hard-cases": only the counter and timestamp extremes (ctest -L hard-cases). */
    if (argc > 1 && strcmp(argv[1], "hard-cases") == 0) {
        test_tick_clock();
        test_counter_extremes();
        test_wraps();
        test_loss_and_backward();
        return tu_finish("test_tracking_parsers hard-cases");
    }
    test_counter_extremes();
    test_21bit();
    test_tick_clock();
    test_rift_hand();
    test_psvr_hand();
    test_vive_hand();
    test_hdk_hand();
    test_round_trips();
    test_wraps();
    test_loss_and_backward();
    test_truncation_and_ids();
    test_random_bytes();
    test_builders();
    return tu_finish("test_tracking_parsers");
}
