/* Funkhouser & Séquin's incremental optimizer (1993 §6), time-limited as Nirenstein et al. (2002
 * §5.5). Two binary heaps over the objects: the highest value of a next step up, and the lowest
 * value of a current step (the one that brought an object to its level). Both are rebuilt in O(n)
 * each frame, since the values change with the view; frame-to-frame coherence keeps the iterations
 * few. Ties follow the greedy's order exactly (value, then object_id, then candidate), which is what
 * makes the converged result equal lod_optimize_greedy's. */
#include <stdint.h>

#include "lod/lod_internal.h"

struct heap {
    uint32_t *item; /* object indices */
    uint32_t *pos;  /* pos[object] = slot in item, UINT32_MAX when absent */
    double *key;    /* key[object] */
    uint32_t size;
    int max_first;  /* 1: highest key on top (ties: lowest id); 0: lowest key (ties: highest id) */
    const uint32_t *id;
};

static int above(const struct heap *h, uint32_t a, uint32_t b)
{
    if (h->key[a] != h->key[b])
        return h->max_first ? h->key[a] > h->key[b] : h->key[a] < h->key[b];
    return h->max_first ? h->id[a] < h->id[b] : h->id[a] > h->id[b];
}

static void place(struct heap *h, uint32_t slot, uint32_t obj)
{
    h->item[slot] = obj;
    h->pos[obj] = slot;
}

static void sift_up(struct heap *h, uint32_t slot)
{
    uint32_t obj = h->item[slot];
    while (slot > 0) {
        uint32_t parent = (slot - 1) / 2;
        if (!above(h, obj, h->item[parent]))
            break;
        place(h, slot, h->item[parent]);
        slot = parent;
    }
    place(h, slot, obj);
}

static void sift_down(struct heap *h, uint32_t slot)
{
    uint32_t obj = h->item[slot];
    for (;;) {
        uint32_t child = 2 * slot + 1;
        if (child >= h->size)
            break;
        if (child + 1 < h->size && above(h, h->item[child + 1], h->item[child]))
            ++child;
        if (!above(h, h->item[child], obj))
            break;
        place(h, slot, h->item[child]);
        slot = child;
    }
    place(h, slot, obj);
}

static void heap_build(struct heap *h)
{
    for (uint32_t s = h->size / 2; s-- > 0;)
        sift_down(h, s);
}

static void heap_remove(struct heap *h, uint32_t obj)
{
    uint32_t slot = h->pos[obj];
    if (slot == UINT32_MAX)
        return;
    h->pos[obj] = UINT32_MAX;
    uint32_t last = h->item[--h->size];
    if (slot == h->size)
        return;
    place(h, slot, last);
    sift_down(h, slot);
    sift_up(h, h->pos[last]);
}

/* Inserts obj with key, or moves it to its new key. */
static void heap_set(struct heap *h, uint32_t obj, double key)
{
    h->key[obj] = key;
    if (h->pos[obj] == UINT32_MAX) {
        place(h, h->size++, obj);
        sift_up(h, h->size - 1);
    } else {
        sift_down(h, h->pos[obj]);
        sift_up(h, h->pos[obj]);
    }
}

struct fs {
    const struct lod_problem *p;
    uint8_t *choice;
    struct heap next, cur;
    int64_t total;
};

/* Brings both heaps in line with object i's choice. */
static void refresh(struct fs *s, uint32_t i)
{
    const struct lod_problem *p = s->p;
    uint32_t c = p->first[i] + s->choice[i];
    if (s->choice[i] + 1 < p->count[i])
        heap_set(&s->next, i, lod_value_of(p, c + 1));
    else
        heap_remove(&s->next, i);
    if (s->choice[i] > 0)
        heap_set(&s->cur, i, lod_value_of(p, c));
    else
        heap_remove(&s->cur, i);
}

static void step(struct fs *s, uint32_t i, int up)
{
    uint32_t c = s->p->first[i] + s->choice[i];
    uint32_t to = up ? c + 1 : c - 1;
    s->total += lod_cost_units(s->p->cost_ms[to]) - lod_cost_units(s->p->cost_ms[c]);
    s->choice[i] = (uint8_t)(s->choice[i] + (up ? 1 : -1));
    refresh(s, i);
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
    int64_t deadline = time_limit_us > 0.0 ? t0 + (int64_t)(time_limit_us * 1e3) : INT64_MAX;
    int64_t budget = lod_budget_units(p->budget_ms);
    *r = (struct lod_result){0};
    size_t n = p->object_count;
    char *at = (char *)(((uintptr_t)scratch + 15u) & ~(uintptr_t)15u);
    struct fs s = {.p = p, .choice = choice};
    s.next = (struct heap){carve(&at, n * 4), carve(&at, n * 4), carve(&at, n * 8), 0, 1, p->object_id};
    s.cur = (struct heap){carve(&at, n * 4), carve(&at, n * 4), carve(&at, n * 8), 0, 0, p->object_id};
    struct lod_step *order = carve(&at, n * sizeof(struct lod_step));

    s.total = lod_choice_sanitize(p, choice, &r->dropped);
    for (uint32_t i = 0; i < n; ++i) {
        s.next.pos[i] = s.cur.pos[i] = UINT32_MAX;
        if (choice[i] == LOD_DROPPED)
            continue;
        uint32_t c = p->first[i] + choice[i];
        if (choice[i] + 1 < p->count[i]) {
            s.next.key[i] = lod_value_of(p, c + 1);
            place(&s.next, s.next.size++, i);
        }
        if (choice[i] > 0) {
            s.cur.key[i] = lod_value_of(p, c);
            place(&s.cur, s.cur.size++, i);
        }
    }
    heap_build(&s.next);
    heap_build(&s.cur);

    /* A start over budget (the view or the budget changed): lower the least valuable steps first,
     * then drop objects if even everything at candidate 0 does not fit. This part always runs: the
     * time limit applies to the improvement, never to feasibility. */
    while (s.total > budget && s.cur.size > 0) {
        step(&s, s.cur.item[0], 0);
        ++r->iterations;
    }
    if (s.total > budget) {
        r->over_budget = 1;
        s.total = lod_drop_to_fit(p, s.total, budget, choice, order, &r->dropped);
        for (uint32_t i = 0; i < n; ++i)
            if (choice[i] == LOD_DROPPED)
                heap_remove(&s.next, i);
    }

    /* §6: raise the best next step, lower the worst current ones until it fits; stop when the
     * raised object is the one lowered. Each pass ends feasible. The iteration cap is a safety net
     * against a problem that was not hull-reduced. */
    uint64_t cap = 4ull * (uint64_t)n * (LOD_MAX_LEVELS + 1) + 16;
    int converged = 0;
    while (r->iterations < cap) {
        if ((r->iterations & 3u) == 0 && hl_clock_now_ns() >= deadline) {
            r->truncated = 1;
            break;
        }
        if (s.next.size == 0) {
            converged = 1;
            break;
        }
        uint32_t raised = s.next.item[0];
        step(&s, raised, 1);
        ++r->iterations;
        int undone = 0;
        while (s.total > budget) {
            uint32_t lowered = s.cur.item[0];
            step(&s, lowered, 0);
            ++r->iterations;
            undone |= lowered == raised;
        }
        if (undone) {
            converged = 1;
            break;
        }
    }

    r->benefit = lod_choice_benefit(p, choice);
    if (converged)
        r->single_item = lod_guard_single_item(p, budget, choice, &r->benefit, &s.total);
    r->cost_ms = (double)s.total / LOD_UNITS_PER_MS;
    r->elapsed_us = (double)(hl_clock_now_ns() - t0) * 1e-3;
}
