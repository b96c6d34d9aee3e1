/* Helpers shared by the report parsers and encoders (not part of the public API). */
#ifndef HMDLOD_TRACKING_REPORT_INTERNAL_H
#define HMDLOD_TRACKING_REPORT_INTERNAL_H

#include "tracking/tracking.h"

/* Little-endian field access: every multi-byte HID field is little-endian unless stated (§2 intro). */
static inline uint16_t trk_rd_u16(const uint8_t *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static inline int16_t trk_rd_i16(const uint8_t *p) { return (int16_t)trk_rd_u16(p); }
static inline uint32_t trk_rd_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static inline void trk_wr_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFF);
    p[1] = (uint8_t)(v >> 8);
}
static inline void trk_wr_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        p[i] = (uint8_t)(v >> (8 * i));
}

/* A zeroed sample with identity orientation and no flags set. */
void trk_sample_clear(struct trk_imu_sample *s);

/* Rounds a physical value to the nearest LSB count and clamps to [lo, hi]; NaN → 0. */
int32_t trk_quantize(double value, double lsb, int32_t lo, int32_t hi);

/* Converts a time to the device counter: round(ns / period) + offset, masked to the width. */
uint32_t trk_ns_to_counter(int64_t time_ns, uint32_t bits, uint32_t period_num_ns, uint32_t period_den,
                           int64_t offset_ticks);

/* Counts a drop for a clock result: 0 → duplicate, −1 → backward. */
static inline void trk_count_drop(struct trk_report_counters *n, int clock_result)
{
    if (clock_result == 0)
        ++n->duplicates;
    else
        ++n->backward;
}

/* Starts the next output sample from a raw device tick: when the unwrapped clock advances, clears
 * *slot, stamps its device time and returns it; otherwise counts the duplicate or backward tick and
 * returns NULL (the sample is dropped). */
struct trk_imu_sample *trk_sample_begin_at_tick(struct trk_tick_clock *clock, struct trk_report_counters *n,
                                                uint32_t raw_ticks, struct trk_imu_sample *slot);

static inline int trk_reject(struct trk_report_counters *n) { ++n->rejected; return -1; }

#endif
