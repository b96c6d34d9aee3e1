/* Shared pieces of the report parsers: counter unwrapping, the Rift 21-bit triples, quantization,
 * the table of supported trackers. DEVICES.md §2 is the reference for every number here. */
#include "tracking/report_internal.h"

#include <math.h>
#include <string.h>

void trk_sample_clear(struct trk_imu_sample *s)
{
    memset(s, 0, sizeof *s);
    s->orientation = hl_q_identity();
}

struct trk_imu_sample *trk_sample_begin_at_tick(struct trk_tick_clock *clock, struct trk_report_counters *n,
                                                uint32_t raw_ticks, struct trk_imu_sample *slot)
{
    int64_t ticks;
    int step = trk_tick_clock_unwrap(clock, raw_ticks, &ticks);
    if (step == -2)
        return NULL; /* the caller sees clock->overflowed and refuses the report */
    if (step <= 0) {
        trk_count_drop(n, step);
        return NULL;
    }
    trk_sample_clear(slot);
    slot->device_time_ns = trk_tick_clock_ns(clock, ticks);
    return slot;
}

/* ---- counter unwrapping ------------------------------------------------------------------------ */

void trk_tick_clock_init(struct trk_tick_clock *clock, uint32_t bits, uint32_t period_num_ns, uint32_t period_den)
{
    memset(clock, 0, sizeof *clock);
    clock->bits = bits < 1 ? 1 : bits > 32 ? 32 : bits;
    clock->period_num_ns = period_num_ns ? period_num_ns : 1;
    clock->period_den = period_den ? period_den : 1;
}

static uint32_t width_mask(uint32_t bits) { return bits >= 32 ? 0xFFFFFFFFu : ((1u << bits) - 1u); }

int trk_tick_clock_unwrap(struct trk_tick_clock *clock, uint32_t raw, int64_t *ticks_out)
{
    uint32_t mask = width_mask(clock->bits);
    raw &= mask;
    if (!clock->started) {
        clock->started = 1;
        clock->last_raw = raw;
        clock->ticks = raw;
        *ticks_out = clock->ticks;
        return 1;
    }
    /* The step modulo 2^bits. Less than half the range forward is a step (across a wrap or not);
     * anything else is the counter going back by at most half the range — a stale or replayed
     * sample (PSVR replays a previous session's queue, §2c), which must not be read as a wrap that
     * would push the clock ~one range into the future. */
    uint32_t d = (raw - clock->last_raw) & mask;
    uint32_t half = clock->bits >= 32 ? 0x80000000u : (1u << (clock->bits - 1));
    if (d == 0) {
        *ticks_out = clock->ticks;
        return 0;
    }
    if (d >= half)
        return -1;
    if (clock->ticks > trk_tick_clock_max_ticks(clock) - (int64_t)d) {
        clock->overflowed = 1;
        return -2;
    }
    clock->last_raw = raw;
    clock->ticks += d;
    *ticks_out = clock->ticks;
    return 1;
}

static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0)))
        --q;
    return q;
}

int64_t trk_tick_clock_max_ticks(const struct trk_tick_clock *clock)
{
    /* ticks·num + den/2 must fit int64: the DK1's 1 ms tick allows 9.2e12 ticks (292 years). */
    return (INT64_MAX - (int64_t)clock->period_den) / (int64_t)clock->period_num_ns;
}

int64_t trk_tick_clock_ns(const struct trk_tick_clock *clock, int64_t ticks)
{
    int64_t scaled;
    if (hl_i64_mul_checked(ticks, (int64_t)clock->period_num_ns, &scaled) != 0 ||
        hl_i64_add_checked(scaled, (int64_t)(clock->period_den / 2), &scaled) != 0)
        return ticks < 0 ? INT64_MIN : INT64_MAX;
    /* Exact rational period (Vive: 125/6 ns = 1/48 MHz) so long runs accumulate no drift. */
    return floor_div(scaled, clock->period_den);
}

uint32_t trk_ns_to_counter(int64_t time_ns, uint32_t bits, uint32_t period_num_ns, uint32_t period_den,
                           int64_t offset_ticks)
{
    /* In 128 bits: time_ns·den overflows int64 past 48 years for the Vive's den = 6, and the counter
     * is taken modulo 2^bits anyway, which the wide result gives exactly. */
    __int128 num = period_num_ns, scaled = (__int128)time_ns * period_den + num / 2;
    __int128 ticks = scaled / num;
    if (scaled % num != 0 && scaled < 0)
        --ticks;
    return (uint32_t)((unsigned __int128)(ticks + offset_ticks) & width_mask(bits));
}

int32_t trk_quantize(double value, double lsb, int32_t lo, int32_t hi)
{
    double c = value / lsb;
    if (!(c == c))
        return 0;
    if (c <= (double)lo)
        return lo;
    if (c >= (double)hi)
        return hi;
    return (int32_t)lround(c);
}

/* ---- Rift 21-bit packed triples (§2b) ------------------------------------------------------------ */

void trk_unpack_21bit_triple(const uint8_t in[8], int32_t out[3])
{
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i)
        v = (v << 8) | in[i]; /* the 8 bytes are one big-endian bit string */
    for (int k = 0; k < 3; ++k) {
        uint32_t field = (uint32_t)(v >> (43 - 21 * k)) & 0x1FFFFFu;
        /* Sign-extend from bit 20 without shifting into the sign bit (UB-free). */
        out[k] = (field & 0x100000u) ? (int32_t)field - 0x200000 : (int32_t)field;
    }
}

void trk_pack_21bit_triple(const int32_t in[3], uint8_t out[8])
{
    uint64_t v = 0;
    for (int k = 0; k < 3; ++k) {
        int32_t c = in[k] < -0x100000 ? -0x100000 : in[k] > 0xFFFFF ? 0xFFFFF : in[k];
        v |= (uint64_t)((uint32_t)c & 0x1FFFFFu) << (43 - 21 * k);
    }
    for (int i = 0; i < 8; ++i)
        out[i] = (uint8_t)(v >> (56 - 8 * i));
}

/* ---- supported trackers (§2a) ---------------------------------------------------------------------
 * IMU rows are the interfaces the parsers read; control rows are where the start commands go. */
const struct trk_device_info trk_device_table[] = {
    /* VR-Tek reuses 2833:0001, hence the manufacturer check (§2a). */
    {"Oculus Rift DK1", TRK_DEVICE_RIFT_DK1, TRK_ROLE_IMU, 0x2833, 0x0001, -1, "Oculus VR, Inc.", 64, 1000.0, 1000.0},
    {"Oculus Rift DK2", TRK_DEVICE_RIFT_DK2, TRK_ROLE_IMU, 0x2833, 0x0021, -1, NULL, 64, 1000.0, 1000.0},
    {"Oculus Rift DK2", TRK_DEVICE_RIFT_DK2, TRK_ROLE_IMU, 0x2833, 0x2021, -1, NULL, 64, 1000.0, 1000.0},
    {"Oculus Rift CV1", TRK_DEVICE_RIFT_CV1, TRK_ROLE_IMU, 0x2833, 0x0031, 0, NULL, 64, 1000.0, 1000.0},
    /* ≈2 kHz samples in ≈1 kHz reports, inferred from the tick spacing (§2a). */
    {"Sony PSVR sensor", TRK_DEVICE_PSVR, TRK_ROLE_IMU, 0x054c, 0x09af, 4, NULL, 64, 2000.0, 1000.0},
    {"Sony PSVR control", TRK_DEVICE_PSVR, TRK_ROLE_CONTROL, 0x054c, 0x09af, 5, NULL, 0, 0.0, 0.0},
    {"HTC Vive IMU", TRK_DEVICE_VIVE, TRK_ROLE_IMU, 0x28de, 0x2000, 0, NULL, 52, 1000.0, 1000.0},
    {"HTC Vive mainboard", TRK_DEVICE_VIVE, TRK_ROLE_CONTROL, 0x0bb4, 0x2c87, 0, NULL, 0, 0.0, 0.0},
    /* Pro and Index share 28de:2300; their axes differ, so the model comes from elsewhere. */
    {"HTC Vive Pro / Valve Index IMU", TRK_DEVICE_VIVE_PRO_INDEX, TRK_ROLE_IMU, 0x28de, 0x2300, 0, NULL, 52, 1000.0, 1000.0},
    {"HTC Vive Pro mainboard", TRK_DEVICE_VIVE_PRO_INDEX, TRK_ROLE_CONTROL, 0x0bb4, 0x0309, 0, NULL, 0, 0.0, 0.0},
    {"HTC Vive Pro 2 mainboard", TRK_DEVICE_VIVE_PRO_INDEX, TRK_ROLE_CONTROL, 0x0bb4, 0x0342, 0, NULL, 0, 0.0, 0.0},
    /* v1.x firmware reports at 100 Hz, v3 at 400 Hz (§2e); the table gives the faster one. */
    {"OSVR HDK", TRK_DEVICE_HDK, TRK_ROLE_IMU, 0x1532, 0x0b00, 2, NULL, 32, 400.0, 400.0},
    {"OSVR HDK (alt)", TRK_DEVICE_HDK, TRK_ROLE_IMU, 0x03eb, 0x2421, -1, NULL, 32, 400.0, 400.0},
};
const size_t trk_device_table_count = sizeof trk_device_table / sizeof trk_device_table[0];

const struct trk_device_info *trk_device_find(uint16_t vid, uint16_t pid, int interface_number)
{
    for (size_t i = 0; i < trk_device_table_count; ++i) {
        const struct trk_device_info *d = &trk_device_table[i];
        if (d->vid == vid && d->pid == pid && (d->interface_number < 0 || d->interface_number == interface_number))
            return d;
    }
    return NULL;
}
