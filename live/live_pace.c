/* Pacing of the live loop at the display's refresh. Where glfwSwapInterval(1) throttles, the swap
 * itself waits for the display; where it does not (Xvfb, some drivers: PLATFORM.md §3), frames are
 * released on the monotonic clock: sleep to just before the slot, then spin the last stretch,
 * because a sleep's wake-up is late by tens to hundreds of microseconds and the issue asks for a
 * present-interval stddev under 1 ms at 90 Hz. */
#include <errno.h>
#include <math.h>
#include <time.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "live/live.h"

enum { LIV_SPIN_NS = 300000 }; /* the last 0.3 ms before a slot are spun, not slept */

static void trim_heap(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
}

void liv_pacer_init(struct liv_pacer *p, double rate_hz, int self_paced, int64_t now_ns)
{
    p->period_ns = (int64_t)llround(1e9 / rate_hz);
    p->t0_ns = now_ns + p->period_ns; /* the first frame is due one period from now */
    p->last_present_ns = 0;
    p->slot = 0;
    p->missed = 0;
    p->self_paced = self_paced;
    p->clock_ns = hl_clock_now_ns;
    p->clock_jumps = 0;
    p->trim = trim_heap;
    p->last_trim_ns = now_ns;
    p->trim_max_ns = 0;
    p->trims = 0;
}

/* In the slack before a frame (its work ends slack_ns before its slot), at most every 10 s. */
static void trim_if_idle(struct liv_pacer *p, int64_t now_ns, int64_t slack_ns)
{
    if (now_ns < p->last_trim_ns)
        p->last_trim_ns = now_ns; /* the clock went back: count the 10 s from here */
    if (!p->trim || slack_ns < LIV_PACER_TRIM_SLACK_NS || now_ns - p->last_trim_ns < LIV_PACER_TRIM_EVERY_NS)
        return;
    p->trim();
    int64_t end_ns = p->clock_ns();
    if (end_ns - now_ns > p->trim_max_ns)
        p->trim_max_ns = end_ns - now_ns;
    p->last_trim_ns = end_ns;
    p->trims++;
}

int64_t liv_pacer_due_ns(const struct liv_pacer *p) { return p->t0_ns + p->slot * p->period_ns; }

void liv_pacer_plan(struct liv_pacer *p, int64_t expected_work_ns)
{
    int64_t now = p->clock_ns(), due = liv_pacer_due_ns(p);
    int64_t ready = now + (expected_work_ns > 0 ? expected_work_ns : 0);
    if (!p->self_paced) {
        trim_if_idle(p, now, due - ready); /* due follows the display's phase (presented) */
        return; /* the display decides; liv_pacer_presented follows it */
    }
    if (ready - due > LIV_PACER_JUMP_NS)
        p->clock_jumps++; /* a stall or a forward jump: the slots it passed are missed below */
    if (ready > due) {
        /* It cannot make its slot: aim at the first one it can (its pose predicted to that), as a
         * display with vsync would show it; the slots skipped are missed. */
        long late = (long)((ready - due + p->period_ns - 1) / p->period_ns);
        p->missed += late;
        p->slot += late;
        due = liv_pacer_due_ns(p);
    }
    trim_if_idle(p, now, due - ready);
}

/* On the monotonic clock, an absolute deadline (a preemption before the call does not lengthen the
 * sleep); on an injected clock (tests), a relative one, since its times mean nothing to the kernel. */
static void sleep_until_ns(const struct liv_pacer *p, int64_t t_ns, int64_t now_ns)
{
    int absolute = p->clock_ns == hl_clock_now_ns;
    int64_t ns = absolute ? t_ns : t_ns - now_ns;
    struct timespec ts = {(time_t)(ns / 1000000000), (long)(ns % 1000000000)}, rem;
    while (clock_nanosleep(CLOCK_MONOTONIC, absolute ? TIMER_ABSTIME : 0, &ts, &rem) == EINTR) {
        if (!absolute)
            ts = rem;
    }
}

void liv_pacer_wait(struct liv_pacer *p)
{
    if (!p->self_paced)
        return; /* the swap waits for the display; liv_pacer_presented counts what it skipped */
    int64_t due = liv_pacer_due_ns(p), now = p->clock_ns();
    if (due - now > LIV_PACER_JUMP_NS + p->period_ns) {
        /* The clock went back: waiting for the old schedule would hang for the jump's length.
         * Re-anchor: this frame is due one period from now. */
        p->clock_jumps++;
        p->t0_ns = now + p->period_ns - p->slot * p->period_ns;
        due = liv_pacer_due_ns(p);
    }
    if (now > due) {
        /* Late: present at once; the slots that went by without a new frame are missed. */
        if (now - due > LIV_PACER_JUMP_NS)
            p->clock_jumps++; /* a stall or a forward jump: its slots were missed all the same */
        long late = (long)((now - due) / p->period_ns) + 1;
        p->missed += late;
        p->slot += late;
        return;
    }
    if (due - now > LIV_SPIN_NS)
        sleep_until_ns(p, due - LIV_SPIN_NS, now);
    while (p->clock_ns() < due) {
    }
}

double liv_pacer_presented(struct liv_pacer *p, int64_t present_ns)
{
    double interval_ms = p->last_present_ns ? (double)(present_ns - p->last_present_ns) * 1e-6 : 0.0;
    if (p->last_present_ns && (interval_ms < 0 || interval_ms > LIV_PACER_JUMP_NS * 1e-6)) {
        /* A clock jump (or a stall) between presents: not an interval. Throttled pacing follows
         * the display's phase from this present on; self-paced slots were fixed by wait. */
        if (!p->self_paced) {
            p->clock_jumps++;
            p->t0_ns = present_ns - p->slot * p->period_ns;
        }
        p->last_present_ns = present_ns;
        p->slot++;
        return 0.0;
    }
    if (!p->self_paced && p->last_present_ns) {
        /* Throttled: a present more than 1.5 periods after the last skipped refreshes. */
        long slots = (long)llround((double)(present_ns - p->last_present_ns) / (double)p->period_ns);
        if (slots > 1) {
            p->missed += slots - 1;
            p->slot += slots - 1;
        }
        p->t0_ns = present_ns - p->slot * p->period_ns; /* follow the display's phase */
    }
    p->last_present_ns = present_ns;
    p->slot++;
    return interval_ms;
}
