/* Funkhouser & Séquin's incremental optimizer (1993 §6), time-limited as Nirenstein et al. (2002
 * §5.5). Two binary heaps over the objects: the highest value of a next step up, and the lowest
 * value of a current step (the one that brought an object to its level). Both are rebuilt in O(n)
 * each frame, since the values change with the view; frame-to-frame coherence keeps the iterations
 * few. Ties follow the greedy's order exactly (value, then object_id, then candidate), which is what
 * makes the converged result equal lod_optimize_greedy's. */
#include <stdint.h>
#include <string.h>

#include "lod/lod_internal.h"

/* Entries hold their key and id, so comparisons touch no other array; pos[] finds an object's slot. */
struct entry {
    double key;
    uint32_t id, obj;
};
struct heap {
    struct entry *e;
    uint32_t *pos;  /* pos[object] = slot, UINT32_MAX when absent */
    uint32_t size;
    int max_first;  /* 1: highest key on top (ties: lowest id); 0: lowest key (ties: highest id) */
};

static inline int above(const struct heap *h, const struct entry *a, const struct entry *b)
{
    if (a->key != b->key)
        return h->max_first ? a->key > b->key : a->key < b->key;
    return h->max_first ? a->id < b->id : a->id > b->id;
}

static void sift_up(struct heap *h, uint32_t slot)
{
    struct entry x = h->e[slot];
    while (slot > 0) {
        uint32_t parent = (slot - 1) / 2;
        if (!above(h, &x, &h->e[parent]))
            break;
        h->e[slot] = h->e[parent];
        h->pos[h->e[slot].obj] = slot;
        slot = parent;
    }
    h->e[slot] = x;
    h->pos[x.obj] = slot;
}

/* track = 0 while building: the slots are written once at the end (heap_build). */
static void sift_down_track(struct heap *h, uint32_t slot, int track)
{
    struct entry x = h->e[slot];
    for (;;) {
        uint32_t child = 2 * slot + 1;
        if (child >= h->size)
            break;
        if (child + 1 < h->size && above(h, &h->e[child + 1], &h->e[child]))
            ++child;
        if (!above(h, &h->e[child], &x))
            break;
        h->e[slot] = h->e[child];
        if (track)
            h->pos[h->e[slot].obj] = slot;
        slot = child;
    }
    h->e[slot] = x;
    if (track)
        h->pos[x.obj] = slot;
}

static void heap_build(struct heap *h)
{
    for (uint32_t s = h->size / 2; s-- > 0;)
        sift_down_track(h, s, 0);
    for (uint32_t s = 0; s < h->size; ++s)
        h->pos[h->e[s].obj] = s;
}

static void heap_remove(struct heap *h, uint32_t obj)
{
    uint32_t slot = h->pos[obj];
    if (slot == UINT32_MAX)
        return;
    h->pos[obj] = UINT32_MAX;
    --h->size;
    if (slot == h->size)
        return;
    uint32_t moved = h->e[h->size].obj;
    h->e[slot] = h->e[h->size];
    h->pos[moved] = slot;
    sift_down_track(h, slot, 1);
    sift_up(h, h->pos[moved]);
}

/* Inserts obj with key, or moves it to its new key. */
static void heap_set(struct heap *h, uint32_t obj, uint32_t id, double key)
{
    uint32_t slot = h->pos[obj];
    if (slot == UINT32_MAX) {
        slot = h->size++;
        h->e[slot] = (struct entry){key, id, obj};
        sift_up(h, slot);
    } else {
        h->e[slot].key = key;
        sift_down_track(h, slot, 1);
        sift_up(h, h->pos[obj]);
    }
}

/* Only the objects near the margin can move in a coherent frame, so each heap holds just those
 * past a filter taken from the start: the next-step heap the steps worth at least the lowest
 * current step (tau_next), the current-step heap those worth at most the highest next step
 * (tau_cur). An excluded entry can only matter once the heap's top crosses its filter; then both
 * heaps are rebuilt over every object (rebuild_full), which restores exactness. */
enum { FS_FILTER_MARGIN = 4 }; /* measured with bench optimizer: 1× rebuilt 3× as often as 4× */

struct fs {
    const struct lod_problem *p;
    uint8_t *choice;
    struct heap next, cur;
    int64_t total;
    double benefit;                 /* Σ benefit of the choice, kept up to date */
    double base_benefit, max_gain;  /* Σ benefit at candidate 0; the largest single object's rise */
    double tau_next, tau_cur;
    uint32_t excluded_next, excluded_cur;
    uint32_t rebuilds;
    int64_t deadline_ns, rebuild_ns; /* the time limit; what a rebuild is expected to take (the set-up's) */
    int stopped;                     /* a rebuild was due but would not end before the deadline */
};

/* Brings both heaps in line with object i's choice. */
static void refresh(struct fs *s, uint32_t i)
{
    const struct lod_problem *p = s->p;
    uint32_t c = p->first[i] + s->choice[i];
    if (s->choice[i] + 1 < p->count[i])
        heap_set(&s->next, i, p->object_id[i], lod_value_of(p, c + 1));
    else
        heap_remove(&s->next, i);
    if (s->choice[i] > 0)
        heap_set(&s->cur, i, p->object_id[i], lod_value_of(p, c));
    else
        heap_remove(&s->cur, i);
}

static void step(struct fs *s, uint32_t i, int up)
{
    const struct lod_problem *p = s->p;
    uint32_t c = p->first[i] + s->choice[i];
    uint32_t to = up ? c + 1 : c - 1;
    s->total += lod_cost_units(p->cost_ms[to]) - lod_cost_units(p->cost_ms[c]);
    s->benefit += p->benefit[to] - p->benefit[c];
    s->choice[i] = (uint8_t)(s->choice[i] + (up ? 1 : -1));
    refresh(s, i);
}

/* Fills both heaps' entry arrays with every object's steps (no filter) and builds them. */
static void rebuild_full(struct fs *s)
{
    const struct lod_problem *p = s->p;
    s->next.size = s->cur.size = 0;
    for (uint32_t i = 0; i < p->object_count; ++i) {
        if (s->choice[i] == LOD_DROPPED)
            continue;
        uint32_t c = p->first[i] + s->choice[i];
        if (s->choice[i] + 1 < p->count[i])
            s->next.e[s->next.size++] = (struct entry){lod_value_of(p, c + 1), p->object_id[i], i};
        if (s->choice[i] > 0)
            s->cur.e[s->cur.size++] = (struct entry){lod_value_of(p, c), p->object_id[i], i};
    }
    memset(s->next.pos, 0xff, p->object_count * sizeof *s->next.pos);
    memset(s->cur.pos, 0xff, p->object_count * sizeof *s->cur.pos);
    heap_build(&s->next);
    heap_build(&s->cur);
    s->tau_next = -INFINITY;
    s->tau_cur = INFINITY;
    s->excluded_next = s->excluded_cur = 0;
    ++s->rebuilds;
}

/* Whether the current-step heap's top may no longer be the lowest: then only an O(n) rebuild says. */
static int cur_needs_rebuild(const struct fs *s)
{
    return s->excluded_cur > 0 && (s->cur.size == 0 || s->cur.e[0].key > s->tau_cur);
}

/* Under a time limit an O(n) rebuild is started only when it should end before the deadline
 * (Nirenstein §5.5: stop with what is feasible rather than overrun). */
static int rebuild_fits(const struct fs *s)
{
    return s->deadline_ns == INT64_MAX || hl_clock_now_ns() + s->rebuild_ns < s->deadline_ns;
}

/* The object with the highest next step, or UINT32_MAX when none can rise (or, under a time
 * limit, when finding it needs a rebuild that would overrun: then s->stopped). */
static uint32_t top_next(struct fs *s)
{
    if (s->excluded_next > 0 && (s->next.size == 0 || s->next.e[0].key < s->tau_next)) {
        if (!rebuild_fits(s)) {
            s->stopped = 1;
            return UINT32_MAX;
        }
        rebuild_full(s);
    }
    return s->next.size ? s->next.e[0].obj : UINT32_MAX;
}

/* The object with the lowest current step, or UINT32_MAX when every object is at candidate 0. */
static uint32_t top_cur(struct fs *s)
{
    if (cur_needs_rebuild(s))
        rebuild_full(s);
    return s->cur.size ? s->cur.e[0].obj : UINT32_MAX;
}

/* The filters are tested without dividing: v = Δb/Δc ≥ τ ⇔ Δb ≥ τ·Δc for Δc > 0. The slack makes
 * the test keep every step whose rounded value reaches τ (it may keep a few more, never fewer),
 * so an excluded step's key is below τ_next (above τ_cur) exactly as the heaps' checks assume.
 * A step that does not cost more (Δc ≤ 0, only in problems not hull-reduced) is always kept. */
#define FS_FILTER_SLACK 1e-12
static inline int reaches(double db, double dc, double tau)
{
    double t = tau * dc;
    return !(dc > 0.0) || db >= t - fabs(t) * FS_FILTER_SLACK;
}
static inline int stays_under(double db, double dc, double tau)
{
    double t = tau * dc;
    return !(dc > 0.0) || db <= t + fabs(t) * FS_FILTER_SLACK;
}

/* The extreme step values of the start, compared by cross-multiplication (Δc > 0), one division
 * at the end. A step with Δc ≤ 0 is worth DBL_MAX (lod_step_value). */
struct ratio {
    double db, dc;
    int any;
};
static inline void ratio_lower(struct ratio *r, double db, double dc)
{
    if (dc > 0.0 && (!r->any || db * r->dc < r->db * dc))
        *r = (struct ratio){db, dc, 1};
}
static inline void ratio_higher(struct ratio *r, double db, double dc)
{
    if (!(dc > 0.0))
        *r = (struct ratio){DBL_MAX, 1.0, 1};
    else if (!r->any || db * r->dc > r->db * dc)
        *r = (struct ratio){db, dc, 1};
}

/* One pass over the objects: makes the choice valid, sums its cost and benefit, finds the extreme
 * step values and, when `write`, stores the entries past the filters tau_next / tau_cur — few in a
 * coherent frame, so the per-frame memory traffic is the inputs, not the heaps. */
struct scan {
    struct ratio lowest_cur, highest_next;
    uint32_t nn, nc; /* objects with a next step, with a current step */
};
static void scan_objects(struct fs *s, int write, uint32_t *dropped, struct scan *out)
{
    const struct lod_problem *p = s->p;
    const double *restrict cost = p->cost_ms, *restrict ben = p->benefit;
    const uint32_t *restrict first = p->first, *restrict id = p->object_id;
    const uint8_t *restrict count = p->count;
    uint8_t *restrict choice = s->choice;
    struct entry *restrict en = s->next.e, *restrict ec = s->cur.e;
    const double tau_next = s->tau_next, tau_cur = s->tau_cur;
    uint32_t n = (uint32_t)p->object_count, nn = 0, nc = 0, none = 0, size_next = 0, size_cur = 0;
    struct ratio lowest_cur = {0, 0, 0}, highest_next = {0, 0, 0};
    double benefit = 0.0, base = 0.0, gain = 0.0;
    int64_t total = 0;
    for (uint32_t i = 0; i < n; ++i) {
        uint8_t k = choice[i], m = count[i];
        if (m == 0) {
            choice[i] = LOD_DROPPED;
            ++none;
            continue;
        }
        if (k >= m)
            choice[i] = k = 0;
        uint32_t c0 = first[i], c = c0 + k;
        total += lod_cost_units(cost[c]);
        benefit += ben[c];
        base += ben[c0];
        double rise = ben[c0 + m - 1] - ben[c0];
        gain = rise > gain ? rise : gain;
        if (k + 1 < m) {
            double db = ben[c + 1] - ben[c], dc = cost[c + 1] - cost[c];
            ratio_higher(&highest_next, db, dc);
            ++nn;
            if (write && reaches(db, dc, tau_next))
                en[size_next++] = (struct entry){lod_value_of(p, c + 1), id[i], i};
        }
        if (k > 0) {
            double db = ben[c] - ben[c - 1], dc = cost[c] - cost[c - 1];
            ratio_lower(&lowest_cur, db, dc);
            ++nc;
            if (write && stays_under(db, dc, tau_cur))
                ec[size_cur++] = (struct entry){lod_value_of(p, c), id[i], i};
        }
    }
    s->total = total;
    s->benefit = benefit;
    s->base_benefit = base;
    s->max_gain = gain;
    s->next.size = size_next, s->cur.size = size_cur;
    *dropped = none;
    *out = (struct scan){lowest_cur, highest_next, nn, nc};
}

/* The filters with a margin: the margin between taken and untaken steps moves during the frame
 * (values change with the view, steps taken lower the marginal value), and every time it leaves
 * the filtered range the heaps must be rebuilt over all objects. Step values span decades, so a
 * factor of FS_FILTER_MARGIN each way keeps the heaps small and the rebuilds rare. Centred on last
 * frame's margin when the caller passes it (one pass), else on this frame's extreme steps, found
 * by a first pass that only reads (objects whose steps cost nothing more leave them unset: then
 * nothing is filtered out). */
static void setup_filtered(struct fs *s, uint32_t *dropped)
{
    const struct lod_problem *p = s->p;
    uint32_t n = (uint32_t)p->object_count;
    struct scan sc;
    double hint = p->value_hint;
    if (hint > 0.0 && hint < DBL_MAX) {
        s->tau_next = hint / FS_FILTER_MARGIN;
        s->tau_cur = hint * FS_FILTER_MARGIN;
    } else {
        scan_objects(s, 0, dropped, &sc);
        s->tau_next = sc.lowest_cur.any ? sc.lowest_cur.db / sc.lowest_cur.dc / FS_FILTER_MARGIN : -INFINITY;
        s->tau_cur = sc.highest_next.any ? sc.highest_next.db / sc.highest_next.dc * FS_FILTER_MARGIN : INFINITY;
    }
    scan_objects(s, 1, dropped, &sc);
    s->excluded_next = sc.nn - s->next.size;
    s->excluded_cur = sc.nc - s->cur.size;
    memset(s->next.pos, 0xff, n * sizeof *s->next.pos);
    memset(s->cur.pos, 0xff, n * sizeof *s->cur.pos);
    heap_build(&s->next);
    heap_build(&s->cur);
}

/* Where taken and untaken steps meet after the run: between the best step not taken and the worst
 * one taken (their geometric mean when both are positive) — the centre of next frame's filters. */
static double margin_value(const struct fs *s)
{
    double vn = s->next.size ? s->next.e[0].key : 0.0, vc = s->cur.size ? s->cur.e[0].key : 0.0;
    if (vn > 0.0 && vc > 0.0 && vn < DBL_MAX && vc < DBL_MAX)
        return sqrt(vn * vc);
    if (vc > 0.0 && vc < DBL_MAX)
        return vc;
    return vn > 0.0 && vn < DBL_MAX ? vn : 0.0;
}

static void *carve(char **at, size_t bytes)
{
    void *p = *at;
    *at += (bytes + 15u) & ~(size_t)15u;
    return p;
}

void lod_optimize_fs(const struct lod_problem *p, double time_limit_us, void *scratch, uint8_t *choice,
                     struct lod_result *r)
{
    int64_t t0 = hl_clock_now_ns();
    /* Saturating: a limit of +inf (or 1e300 us) means none, not an undefined conversion. */
    int64_t deadline = INT64_MAX;
    if (time_limit_us > 0.0 && hl_i64_add_checked(t0, hl_i64_from_double_saturating(time_limit_us * 1e3), &deadline) != 0)
        deadline = INT64_MAX;
    int64_t budget = lod_budget_units(p->budget_ms);
    *r = (struct lod_result){0};
    size_t n = p->object_count;
    char *at = (char *)(((uintptr_t)scratch + 15u) & ~(uintptr_t)15u);
    struct fs s = {.p = p, .choice = choice};
    s.next = (struct heap){carve(&at, n * sizeof(struct entry)), carve(&at, n * 4), 0, 1};
    s.cur = (struct heap){carve(&at, n * sizeof(struct entry)), carve(&at, n * 4), 0, 0};
    struct lod_step *order = carve(&at, n * sizeof(struct lod_step));
    setup_filtered(&s, &r->dropped);

    /* A start over budget (the view or the budget changed): lower the least valuable steps first,
     * then drop objects if even everything at candidate 0 does not fit. This part always runs: the
     * time limit applies to the improvement, never to feasibility. */
    for (uint32_t low; s.total > budget && (low = top_cur(&s)) != UINT32_MAX;) {
        step(&s, low, 0);
        ++r->iterations;
    }
    if (s.total > budget) {
        r->over_budget = 1;
        s.total = lod_drop_to_fit(p, s.total, budget, choice, order, &r->dropped);
        s.benefit = lod_choice_benefit(p, choice);
        rebuild_full(&s);
    }

    /* §6: raise the best next step, lower the worst current ones until it fits; stop when the
     * raised object is the one lowered. Each pass ends feasible. The iteration cap is a safety net
     * against a problem that was not hull-reduced. */
    uint64_t cap = 4ull * (uint64_t)n * (LOD_MAX_LEVELS + 1) + 16;
    int converged = 0, limited = deadline != INT64_MAX;
    int64_t t_setup = hl_clock_now_ns();
    r->setup_us = (double)(t_setup - t0) * 1e-3;
    s.deadline_ns = deadline, s.rebuild_ns = t_setup - t0;
    /* Still over after the drops: the objects the caller keeps exceed the budget alone. Nothing can
     * be raised (the greedy stops at its first step for the same reason), and nothing is left to
     * lower: the choice stands as it is. */
    if (s.total > budget)
        converged = 1, cap = 0;
    while (r->iterations < cap) {
        if (limited && hl_clock_now_ns() >= deadline) {
            r->truncated = 1;
            break;
        }
        uint32_t raised = top_next(&s);
        if (raised == UINT32_MAX) {
            converged = !s.stopped;
            r->truncated = s.stopped;
            break;
        }
        step(&s, raised, 1);
        ++r->iterations;
        int undone = 0;
        while (s.total > budget) {
            /* A rebuild that would overrun is not started: taking back the raise is feasible at once
             * (the state before it fitted, and every lowering since only saved cost). */
            if (limited && cur_needs_rebuild(&s) && !rebuild_fits(&s)) {
                step(&s, raised, 0);
                ++r->iterations;
                r->truncated = 1;
                break;
            }
            uint32_t lowered = top_cur(&s);
            if (lowered == UINT32_MAX) { /* cannot happen from a feasible start; never index with it */
                step(&s, raised, 0);
                ++r->iterations;
                undone = 1;
                break;
            }
            step(&s, lowered, 0);
            ++r->iterations;
            undone |= lowered == raised;
        }
        if (r->truncated)
            break;
        if (undone) {
            converged = 1;
            break;
        }
    }

    r->benefit = s.benefit;
    if (converged && lod_guard_may_switch(s.base_benefit, s.max_gain, r->benefit))
        r->single_item = lod_guard_single_item(p, budget, choice, &r->benefit, &s.total);
    r->cost_ms = (double)s.total / LOD_UNITS_PER_MS;
    r->heap_rebuilds = s.rebuilds;
    r->margin_value = margin_value(&s);
    r->elapsed_us = (double)(hl_clock_now_ns() - t0) * 1e-3;
}
