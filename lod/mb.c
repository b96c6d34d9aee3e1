/* Mason & Blake's incremental hierarchical optimizer (1997 §4) with Nirenstein et al.'s time limit
 * (2002 §5.5). The representation tree is the caller's plain arrays (lod.h, struct lod_tree); this
 * file keeps, per node, the highest value of a step up and the lowest value of a step down anywhere
 * in its part of the representation tree (with the terminal node that has it), so each iteration
 * descends nowhere: the root's stored terminal is the one to change, and only the path from it to
 * the root is recomputed, post-order, as §4 prescribes.
 *
 * Values are those of hull steps, Δbenefit / Δcost, as in the flat greedy (Funkhouser & Séquin §6),
 * so a tree without groups gives the greedy's answer. Opening a group replaces its top impostor by
 * all its children at their cheapest: in §6's terms the replacement set R taken as one item, whose
 * value is what it adds per millisecond. Fits are decided in the flat optimizers' integer cost units
 * (lod_internal.h), so "within budget" is exact and the same as theirs however the sum was reached. */
#include "lod/lod_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { NONE = UINT32_MAX };

struct mb_drop { /* a representation-tree leaf that may be dropped when even the cheapest does not fit */
    double value;
    uint32_t id, node;
};

struct mb_entry { /* one slot of the imaginary root's tournaments: a root's best step */
    double value;
    uint32_t id, term; /* the terminal's node_id and index; term NONE: no step */
};

struct mb {
    const struct lod_tree *t;
    uint8_t *state;
    double *min_cost, *min_benefit;   /* the node's cheapest representation */
    double *max_benefit;              /* the most any representation of the node earns (the guard's pre-check) */
    double *open_cost, *open_benefit; /* Σ of its children's cheapest: the price of opening it */
    double *hi_val, *lo_val;          /* best step up / down in the node's representation subtree */
    int64_t *min_units, *open_units, *path_units; /* the same costs in integer units */
    struct mb_drop *drop;
    uint32_t *hi_term, *lo_term;      /* the terminal node with that step, NONE when there is none */
    uint32_t *nonmin;                 /* children not at their cheapest (a group closes only at 0) */
    struct mb_entry *tour[2];         /* the imaginary root: tournaments over the roots by hi and by lo */
    uint32_t *slot, *roots;           /* a root's leaf in the tournaments; the roots in node order */
    uint32_t root_count;
    uint8_t *eff;                     /* candidates the node may take (a group's impostors after §3's check) */
    uint8_t *atmin;                   /* 1: the node is at its cheapest representation */
    uint8_t *mark;
    int64_t units, budget;            /* Σ cost units of the current choice; the budget in units */
    double benefit;
};

static size_t align8(size_t n) { return (n + 7u) & ~(size_t)7u; }

size_t lod_mb_scratch_bytes(size_t max_nodes)
{
    size_t n = max_nodes ? max_nodes : 1;
    return align8(7 * n * sizeof(double)) + align8(4 * (n + 1) * sizeof(struct mb_entry)) + align8(3 * n * sizeof(int64_t)) + align8(n * sizeof(struct mb_drop)) + align8(5 * n * sizeof(uint32_t)) +
           align8(3 * n) + 64;
}

static void mb_carve(struct mb *m, void *scratch, size_t n)
{
    char *p = (char *)(((uintptr_t)scratch + 7u) & ~(uintptr_t)7u);
    double *d = (double *)p;
    m->min_cost = d, m->min_benefit = d + n, m->open_cost = d + 2 * n, m->open_benefit = d + 3 * n;
    m->hi_val = d + 4 * n, m->lo_val = d + 5 * n, m->max_benefit = d + 6 * n;
    p += align8(7 * n * sizeof(double));
    m->tour[0] = (struct mb_entry *)p, m->tour[1] = (struct mb_entry *)p + 2 * (n + 1);
    p += align8(4 * (n + 1) * sizeof(struct mb_entry));
    int64_t *w = (int64_t *)p;
    m->min_units = w, m->open_units = w + n, m->path_units = w + 2 * n;
    p += align8(3 * n * sizeof(int64_t));
    m->drop = (struct mb_drop *)p;
    p += align8(n * sizeof(struct mb_drop));
    uint32_t *u = (uint32_t *)p;
    m->hi_term = u, m->lo_term = u + n, m->nonmin = u + 2 * n;
    m->slot = u + 3 * n, m->roots = u + 4 * n;
    p += align8(5 * n * sizeof(uint32_t));
    m->eff = (uint8_t *)p, m->atmin = (uint8_t *)p + n, m->mark = (uint8_t *)p + 2 * n;
}

static inline double cand_cost(const struct lod_tree *t, uint32_t n, unsigned k) { return t->cost_ms[t->first[n] + k]; }
static inline double cand_benefit(const struct lod_tree *t, uint32_t n, unsigned k) { return t->benefit[t->first[n] + k]; }
static inline int64_t cand_units(const struct lod_tree *t, uint32_t n, unsigned k)
{
    return lod_cost_units(t->cost_ms[t->first[n] + k]);
}
static inline int is_leaf(const struct lod_tree *t, uint32_t n) { return t->child_count[n] == 0; }
static inline int is_choice(uint8_t s) { return s < LOD_MB_BELOW; }

/* A step's value; a step that costs nothing and earns something comes first (after lod_hull_reduce
 * there is none, but a caller's own candidates may have one). */
static inline double step_value(double dc, double db)
{
    if (dc > 0.0)
        return db / dc;
    return db > 0.0 ? DBL_MAX : 0.0;
}

static inline double step_up_value(const struct lod_tree *t, uint32_t n, unsigned k) /* k → k + 1 */
{
    return step_value(cand_cost(t, n, k + 1) - cand_cost(t, n, k), cand_benefit(t, n, k + 1) - cand_benefit(t, n, k));
}

static inline double open_value(const struct mb *m, uint32_t n) /* top impostor → children at their cheapest */
{
    unsigned top = m->eff[n] - 1u;
    return step_value(m->open_cost[n] - cand_cost(m->t, n, top), m->open_benefit[n] - cand_benefit(m->t, n, top));
}

/* Ties: the lower node_id rises first and the higher falls first, so a decrement undoes the last of
 * equal increments — the order of the flat greedy's sorted steps. */
static inline int hi_better(const struct mb *m, double va, uint32_t ta, double vb, uint32_t tb)
{
    if (ta == NONE || tb == NONE)
        return ta != NONE;
    return va > vb || (va == vb && m->t->node_id[ta] < m->t->node_id[tb]);
}

static inline int lo_better(const struct mb *m, double va, uint32_t ta, double vb, uint32_t tb)
{
    if (ta == NONE || tb == NONE)
        return ta != NONE;
    return va < vb || (va == vb && m->t->node_id[ta] > m->t->node_id[tb]);
}

/* ---- the imaginary root: two tournament trees over the roots ------------------------------------
 * Leaves at [R, 2R), node i the better of 2i and 2i + 1, the winner at 1 (any R ≥ 1): built in R − 1
 * comparisons of contiguous entries each frame, a root's change replayed in log R. which = 0: the
 * highest step up (ties: lower id); 1: the lowest step down (ties: higher id). */

static inline struct mb_entry root_entry(const struct mb *m, int which, uint32_t root)
{
    uint32_t term = which == 0 ? m->hi_term[root] : m->lo_term[root];
    int none = term == NONE; /* selects, not branches: which roots have a step is unpredictable */
    double value = which == 0 ? m->hi_val[root] : m->lo_val[root];
    uint32_t id = m->t->node_id[none ? 0 : term];
    double absent = which == 0 ? -INFINITY : INFINITY;
    return (struct mb_entry){none ? absent : value, none ? (which == 0 ? UINT32_MAX : 0) : id, term};
}

/* 1 when b beats a; written with bitwise operators and used as an index, not a branch: a
 * tournament's comparisons of unrelated values are a coin toss for the branch predictor, and the
 * per-frame builds were most of mb's set-up. */
static inline unsigned tour_second_wins(int which, const struct mb_entry *a, const struct mb_entry *b)
{
    if (which == 0)
        return !((a->value > b->value) | ((a->value == b->value) & (a->id < b->id)));
    return !((a->value < b->value) | ((a->value == b->value) & (a->id > b->id)));
}

static void tour_build(struct mb *m, int which, const uint32_t *roots)
{
    struct mb_entry *e = m->tour[which];
    uint32_t r = m->root_count;
    for (uint32_t k = 0; k < r; ++k)
        e[r + k] = root_entry(m, which, roots[k]);
    for (uint32_t i = r; i-- > 1;)
        e[i] = e[2 * i + tour_second_wins(which, &e[2 * i], &e[2 * i + 1])];
}

static void tour_update(struct mb *m, int which, uint32_t root)
{
    struct mb_entry *e = m->tour[which];
    uint32_t i = m->root_count + m->slot[root];
    e[i] = root_entry(m, which, root);
    for (i >>= 1; i >= 1; i >>= 1)
        e[i] = e[2 * i + tour_second_wins(which, &e[2 * i], &e[2 * i + 1])];
}

static inline uint32_t tour_winner(const struct mb *m, int which) { return m->tour[which][1].term; }

/* ---- per-node values ----------------------------------------------------------------------------- */

/* Recomputes node n's own steps and its subtree's best ones from its children's (already current). */
static void node_update(struct mb *m, uint32_t n)
{
    const struct lod_tree *t = m->t;
    uint8_t s = m->state[n];
    double hv = -DBL_MAX, lv = DBL_MAX;
    uint32_t ht = NONE, lt = NONE;
    if (s == LOD_MB_OPEN) {
        const uint32_t *ch = t->child + t->first_child[n];
        for (uint32_t k = 0; k < t->child_count[n]; ++k) {
            uint32_t c = ch[k];
            if (hi_better(m, m->hi_val[c], m->hi_term[c], hv, ht))
                hv = m->hi_val[c], ht = m->hi_term[c];
            if (lo_better(m, m->lo_val[c], m->lo_term[c], lv, lt))
                lv = m->lo_val[c], lt = m->lo_term[c];
        }
        /* Closing: only from the lowest implicit representation, every child at its cheapest (§4). */
        if (m->eff[n] > 0 && m->nonmin[n] == 0) {
            double v = open_value(m, n);
            if (lo_better(m, v, n, lv, lt))
                lv = v, lt = n;
        }
        m->atmin[n] = m->eff[n] == 0 && m->nonmin[n] == 0;
    } else if (is_choice(s)) {
        if (s + 1u < m->eff[n])
            hv = step_up_value(t, n, s), ht = n;
        else if (!is_leaf(t, n))
            hv = open_value(m, n), ht = n;
        if (s >= 1)
            lv = step_up_value(t, n, s - 1u), lt = n;
        m->atmin[n] = s == 0;
    } else { /* dropped, or below the tree */
        m->atmin[n] = 1;
    }
    m->hi_val[n] = hv, m->hi_term[n] = ht, m->lo_val[n] = lv, m->lo_term[n] = lt;
}

/* After a change at n: n and its ancestors, post-order along the path only. */
static void path_update(struct mb *m, uint32_t n)
{
    for (uint32_t x = n;;) {
        uint8_t was_min = m->atmin[x];
        node_update(m, x);
        uint32_t p = m->t->parent[x];
        if (p == LOD_MB_ROOT) {
            tour_update(m, 0, x);
            tour_update(m, 1, x);
            return;
        }
        if (m->atmin[x] != was_min)
            m->nonmin[p] += m->atmin[x] ? (uint32_t)-1 : 1u;
        x = p;
    }
}

/* Node n enters the representation tree at its cheapest representation (a group without impostor
 * opens into its children, recursively). Recursion depth is the hierarchy's depth. */
static void node_activate_cheapest(struct mb *m, uint32_t n)
{
    const struct lod_tree *t = m->t;
    m->nonmin[n] = 0;
    if (is_leaf(t, n)) {
        m->state[n] = t->count[n] ? 0 : LOD_DROPPED;
    } else if (m->eff[n] > 0) {
        m->state[n] = 0;
    } else {
        m->state[n] = LOD_MB_OPEN;
        const uint32_t *ch = t->child + t->first_child[n];
        for (uint32_t k = 0; k < t->child_count[n]; ++k)
            node_activate_cheapest(m, ch[k]); /* every child ends at its cheapest: nonmin stays 0 */
    }
    node_update(m, n);
}

/* Everything under n leaves the representation tree. */
static void subtree_deactivate(struct mb *m, uint32_t n)
{
    const struct lod_tree *t = m->t;
    const uint32_t *ch = t->child + t->first_child[n];
    for (uint32_t k = 0; k < t->child_count[n]; ++k) {
        uint32_t c = ch[k];
        if (m->state[c] == LOD_MB_BELOW)
            continue; /* its own subtree is below already */
        m->state[c] = LOD_MB_BELOW;
        subtree_deactivate(m, c);
        node_update(m, c);
    }
}

static void node_increment(struct mb *m, uint32_t n)
{
    const struct lod_tree *t = m->t;
    uint8_t s = m->state[n];
    if (s + 1u < m->eff[n]) {
        m->units += cand_units(t, n, s + 1u) - cand_units(t, n, s);
        m->benefit += cand_benefit(t, n, s + 1u) - cand_benefit(t, n, s);
        m->state[n] = (uint8_t)(s + 1u);
    } else { /* open into the children at their cheapest */
        m->units += m->open_units[n] - cand_units(t, n, s);
        m->benefit += m->open_benefit[n] - cand_benefit(t, n, s);
        m->state[n] = LOD_MB_OPEN;
        m->nonmin[n] = 0;
        const uint32_t *ch = t->child + t->first_child[n];
        for (uint32_t k = 0; k < t->child_count[n]; ++k)
            node_activate_cheapest(m, ch[k]);
    }
    path_update(m, n);
}

static void node_decrement(struct mb *m, uint32_t n)
{
    const struct lod_tree *t = m->t;
    uint8_t s = m->state[n];
    if (s == LOD_MB_OPEN) { /* close: every child is at its cheapest */
        unsigned top = m->eff[n] - 1u;
        m->units -= m->open_units[n] - cand_units(t, n, top);
        m->benefit -= m->open_benefit[n] - cand_benefit(t, n, top);
        m->state[n] = (uint8_t)top;
        subtree_deactivate(m, n);
    } else {
        m->units -= cand_units(t, n, s) - cand_units(t, n, s - 1u);
        m->benefit -= cand_benefit(t, n, s) - cand_benefit(t, n, s - 1u);
        m->state[n] = (uint8_t)(s - 1u);
    }
    path_update(m, n);
}

/* ---- set-up ---------------------------------------------------------------------------------------- */

/* Children first (parents are stored first, so in reverse): each node's cheapest representation, the
 * price of opening it, and the impostor candidates §3 allows. An impostor must cost less and earn less
 * than its children at their cheapest (else opening would not be a step up and the group could never
 * be closed again sensibly); a top impostor under the hull through the opening (the step into it worth
 * less than the step out of it) would be skipped by the greedy, so it is dropped too. A group left
 * with none is always implicit, as if it had no impostor. */
static void mb_prepare(struct mb *m)
{
    const struct lod_tree *t = m->t;
    for (size_t i = t->node_count; i-- > 0;) {
        uint32_t n = (uint32_t)i;
        unsigned e = t->count[n];
        if (is_leaf(t, n)) {
            m->eff[n] = (uint8_t)e;
            m->min_cost[n] = e ? cand_cost(t, n, 0) : 0.0;
            m->min_units[n] = e ? cand_units(t, n, 0) : 0;
            m->open_units[n] = 0;
            m->max_benefit[n] = e ? cand_benefit(t, n, e - 1) : 0.0;
            m->min_benefit[n] = e ? cand_benefit(t, n, 0) : 0.0;
            m->open_cost[n] = m->open_benefit[n] = 0.0;
            continue;
        }
        double oc = 0.0, ob = 0.0, mb = 0.0;
        int64_t ou = 0;
        const uint32_t *ch = t->child + t->first_child[n];
        for (uint32_t k = 0; k < t->child_count[n]; ++k) {
            oc += m->min_cost[ch[k]], ob += m->min_benefit[ch[k]], ou += m->min_units[ch[k]];
            mb += m->max_benefit[ch[k]];
        }
        while (e > 0 && !(cand_units(t, n, e - 1) < ou && cand_benefit(t, n, e - 1) < ob))
            --e;
        while (e >= 2 && step_up_value(t, n, e - 2) <
                             step_value(oc - cand_cost(t, n, e - 1), ob - cand_benefit(t, n, e - 1)))
            --e;
        m->eff[n] = (uint8_t)e;
        m->open_cost[n] = oc, m->open_benefit[n] = ob;
        m->min_cost[n] = e ? cand_cost(t, n, 0) : oc;
        m->open_units[n] = ou;
        m->max_benefit[n] = e && cand_benefit(t, n, e - 1) > mb ? cand_benefit(t, n, e - 1) : mb;
        m->min_units[n] = e ? cand_units(t, n, 0) : ou;
        m->min_benefit[n] = e ? cand_benefit(t, n, 0) : ob;
    }
}

/* Parents first: last frame's state made consistent with this frame's tree. */
static void mb_repair_state(struct mb *m)
{
    const struct lod_tree *t = m->t;
    for (size_t i = 0; i < t->node_count; ++i) {
        uint32_t n = (uint32_t)i, p = t->parent[n];
        uint8_t s = m->state[n], e = m->eff[n];
        if (p != LOD_MB_ROOT && m->state[p] != LOD_MB_OPEN) {
            m->state[n] = LOD_MB_BELOW;
            continue;
        }
        if (is_leaf(t, n)) {
            if (e == 0)
                s = LOD_DROPPED;
            else if (is_choice(s))
                s = s < e ? s : (uint8_t)(e - 1u);
            else
                s = 0; /* unseen, below, open or dropped last frame: start at the cheapest */
        } else if (e == 0) {
            s = LOD_MB_OPEN;
        } else if (is_choice(s)) {
            s = s < e ? s : (uint8_t)(e - 1u);
        } else if (s != LOD_MB_OPEN) {
            s = 0;
        }
        m->state[n] = s;
    }
}

void lod_mb_start_cheapest(const struct lod_tree *t, uint8_t *state)
{
    /* Every node at candidate 0 as far as the tree tells; lod_optimize_mb's repair opens the groups
     * left without impostor and fills their children with their cheapest. */
    for (size_t n = 0; n < t->node_count; ++n) {
        uint32_t p = t->parent[n];
        int in_tree = p == LOD_MB_ROOT || state[p] == LOD_MB_OPEN;
        if (!in_tree)
            state[n] = LOD_MB_BELOW;
        else if (t->count[n] > 0)
            state[n] = 0;
        else
            state[n] = t->child_count[n] ? LOD_MB_OPEN : LOD_DROPPED;
    }
}

static int drop_cmp(const void *a, const void *b)
{
    const struct mb_drop *x = a, *y = b;
    if (x->value != y->value)
        return x->value < y->value ? -1 : 1;
    return x->id < y->id ? -1 : x->id > y->id;
}

static int drop_cmp_desc(const void *a, const void *b) /* value falling, ties: the lower id first */
{
    const struct mb_drop *x = a, *y = b;
    if (x->value != y->value)
        return x->value > y->value ? -1 : 1;
    return x->id < y->id ? -1 : x->id > y->id;
}

/* Rule (2): even the cheapest representation exceeds the budget. Its leaves go, lowest benefit per
 * cost first, until the rest fits (leaves that cost nothing never help and stay); then those that
 * still fit come back, highest benefit per cost first — drops are the last resort, the rule of
 * lod_drop_to_fit (choice.c), so a tree without groups stays equal to the greedy. The set is chosen
 * on the list before any state changes, so the tree's bookkeeping only ever sees final drops. */
static uint32_t mb_drop_over_budget(struct mb *m)
{
    const struct lod_tree *t = m->t;
    uint32_t k = 0;
    for (uint32_t n = 0; n < (uint32_t)t->node_count; ++n) {
        uint8_t s = m->state[n];
        if (!is_choice(s) || cand_cost(t, n, s) <= 0.0)
            continue;
        m->drop[k++] = (struct mb_drop){cand_benefit(t, n, s) / cand_cost(t, n, s), t->node_id[n], n};
    }
    qsort(m->drop, k, sizeof *m->drop, drop_cmp);
    int64_t units = m->units;
    uint32_t gone = 0;
    for (; gone < k && units > m->budget; ++gone)
        units -= cand_units(t, m->drop[gone].node, m->state[m->drop[gone].node]);
    qsort(m->drop, gone, sizeof *m->drop, drop_cmp_desc);
    for (uint32_t j = 0; j < gone; ++j) {
        int64_t u = cand_units(t, m->drop[j].node, m->state[m->drop[j].node]);
        if (units + u <= m->budget) {
            units += u;
            m->drop[j].node = NONE; /* stays */
        }
    }
    uint32_t dropped = 0;
    for (uint32_t j = 0; j < gone; ++j) {
        uint32_t n = m->drop[j].node;
        if (n == NONE)
            continue;
        m->units -= cand_units(t, n, m->state[n]);
        m->benefit -= cand_benefit(t, n, m->state[n]);
        m->state[n] = LOD_DROPPED;
        subtree_deactivate(m, n);
        path_update(m, n);
        ++dropped;
    }
    return dropped;
}

int lod_tree_underused_drop(const struct lod_tree *t, const uint8_t *state, double fraction)
{
    int64_t budget = lod_budget_units(t->budget_ms), total = 0, smallest = INT64_MAX;
    for (uint32_t n = 0; n < (uint32_t)t->node_count; ++n) {
        uint8_t s = state[n];
        if (t->count[n] == 0)
            continue; /* a leaf without a valid candidate, or a group without impostor: never a budget drop */
        if (s == LOD_DROPPED) {
            int64_t u = cand_units(t, n, 0);
            smallest = u < smallest ? u : smallest;
        } else if (is_choice(s) && s < t->count[n]) {
            total += cand_units(t, n, s);
        }
    }
    if (smallest == INT64_MAX || !((double)total < fraction * (double)budget))
        return 0;
    return total <= budget && smallest <= budget - total;
}

/* Mason & Blake §6's guard, with "item" read on the tree: the cheapest representation with one node
 * brought into it (its ancestors opened, their other children at their cheapest) at one of its
 * candidates — so a group's opening, the step the greedy may have split, is an item too. The best
 * that fits replaces the greedy's answer when it earns more (returns 1, written into state).
 * O(candidates); lo_val is free by now and holds, with path_units, each node's price of being present. */
static int mb_single_item(struct mb *m)
{
    const struct lod_tree *t = m->t;
    /* Pre-check, O(roots): a single item lies under one root, so it earns at most that root's best
     * over its cheapest; when even the largest such rise cannot beat the answer, nothing can. */
    double base_b = 0.0, max_gain = 0.0;
    for (size_t i = 0; i < t->node_count; ++i)
        if (t->parent[i] == LOD_MB_ROOT) {
            base_b += m->min_benefit[i];
            double gain = m->max_benefit[i] - m->min_benefit[i];
            max_gain = gain > max_gain ? gain : max_gain;
        }
    if (!(base_b + max_gain > m->benefit - 1e-9 * fabs(m->benefit)))
        return 0;
    /* Nodes dropped over budget stay dropped, with everything under them (mark bit 1). */
    enum { EXCLUDED = 1, OPENED = 2 };
    base_b = 0.0;
    double *path_b = m->lo_val;
    int64_t base_u = 0, *path_u = m->path_units;
    for (size_t i = 0; i < t->node_count; ++i) {
        uint32_t n = (uint32_t)i, p = t->parent[n];
        m->mark[n] = m->state[n] == LOD_DROPPED || (p != LOD_MB_ROOT && (m->mark[p] & EXCLUDED)) ? EXCLUDED : 0;
        if (m->state[n] == LOD_DROPPED) /* a leaf of the cheapest tree: it leaves the base */
            base_u -= m->min_units[n], base_b -= m->min_benefit[n];
        if (p == LOD_MB_ROOT) {
            base_u += m->min_units[n], base_b += m->min_benefit[n];
            path_u[n] = 0, path_b[n] = 0.0;
        } else { /* the parent present, then opened from its cheapest */
            path_u[n] = path_u[p] + m->open_units[p] - m->min_units[p];
            path_b[n] = path_b[p] + m->open_benefit[p] - m->min_benefit[p];
        }
    }
    double best_b = base_b;
    uint32_t best_n = NONE;
    unsigned best_k = 0;
    for (size_t i = 0; i < t->node_count; ++i) {
        uint32_t n = (uint32_t)i;
        if (m->mark[n] & EXCLUDED)
            continue;
        for (unsigned k = 0; k < m->eff[n]; ++k) {
            int64_t u = base_u + path_u[n] + cand_units(t, n, k) - m->min_units[n];
            double b = base_b + path_b[n] + cand_benefit(t, n, k) - m->min_benefit[n];
            if (u <= m->budget && b > best_b)
                best_b = b, best_n = n, best_k = k;
        }
    }
    /* Against the answer's exact sum, by more than rounding: a single item equal to the answer
     * (summed in another order) is no better. */
    double answer = 0.0;
    for (size_t i = 0; i < t->node_count; ++i)
        if (is_choice(m->state[i]))
            answer += cand_benefit(t, (uint32_t)i, m->state[i]);
    if (base_u > m->budget || !(best_b > answer + 1e-12 * fabs(answer)))
        return 0;
    if (best_n != NONE)
        for (uint32_t a = t->parent[best_n]; a != LOD_MB_ROOT; a = t->parent[a])
            m->mark[a] |= OPENED;
    for (size_t i = 0; i < t->node_count; ++i) {
        uint32_t n = (uint32_t)i, p = t->parent[n];
        if (!(p == LOD_MB_ROOT || m->state[p] == LOD_MB_OPEN))
            m->state[n] = LOD_MB_BELOW;
        else if (m->mark[n] & EXCLUDED)
            m->state[n] = LOD_DROPPED;
        else if (n == best_n)
            m->state[n] = (uint8_t)best_k;
        else if (is_leaf(t, n))
            m->state[n] = t->count[n] ? 0 : LOD_DROPPED;
        else
            m->state[n] = m->eff[n] && !(m->mark[n] & OPENED) ? 0 : LOD_MB_OPEN;
    }
    return 1;
}

void lod_optimize_mb(const struct lod_tree *t, double time_limit_us, void *scratch, uint8_t *state,
                     struct lod_result *r)
{
    int64_t t0 = hl_clock_now_ns();
    memset(r, 0, sizeof *r);
    if (t->node_count == 0)
        return;
    struct mb m = {.t = t, .state = state};
    mb_carve(&m, scratch, t->node_count);
    m.budget = lod_budget_units(t->budget_ms);
    mb_prepare(&m);
    mb_repair_state(&m);

    /* Initialisation (§4): every value bottom-up, the roots into the imaginary root's tournaments. */
    size_t candidates = 0;
    for (size_t i = t->node_count; i-- > 0;) {
        uint32_t n = (uint32_t)i;
        candidates += t->count[n];
        m.nonmin[n] = 0;
        if (!is_leaf(t, n) && state[n] == LOD_MB_OPEN) {
            const uint32_t *ch = t->child + t->first_child[n];
            for (uint32_t k = 0; k < t->child_count[n]; ++k)
                m.nonmin[n] += !m.atmin[ch[k]];
        }
        node_update(&m, n);
        if (is_choice(state[n]))
            m.units += cand_units(t, n, state[n]), m.benefit += cand_benefit(t, n, state[n]);
    }
    uint32_t *roots = m.roots;
    for (uint32_t n = 0; n < (uint32_t)t->node_count; ++n)
        if (t->parent[n] == LOD_MB_ROOT) {
            m.slot[n] = m.root_count;
            roots[m.root_count++] = n;
        }
    tour_build(&m, 0, roots);
    tour_build(&m, 1, roots);

    /* Values that do not fall with detail could cycle; no honest run needs more than this. */
    const uint64_t cap = 4u * ((uint64_t)candidates + t->node_count) + 64u;
    const int64_t limit_ns = time_limit_us > 0.0 ? hl_i64_from_double_saturating(time_limit_us * 1e3) : 0; /* +inf: none */
    uint64_t iterations = 0;
    int over = 0, stuck = 0;
    for (;;) {
        /* Nirenstein §5.5: stop only between iterations, when the choice is within budget; the clock
         * runs from the call (set-up included), and one iteration always runs so that frames whose
         * set-up alone uses the limit still make progress: the skipped work is repaid later. */
        if (limit_ns > 0 && iterations > 0 && m.units <= m.budget && hl_clock_now_ns() - t0 >= limit_ns) {
            r->truncated = 1;
            break;
        }
        if (iterations >= cap)
            break;
        uint32_t up = tour_winner(&m, 0);
        if (up == NONE && m.units <= m.budget)
            break; /* rule 1 */
        if (up != NONE) {
            node_increment(&m, up);
            ++iterations;
        }
        int same = 0;
        while (m.units > m.budget) {
            uint32_t down = tour_winner(&m, 1);
            if (down == NONE) { /* rule 2 */
                stuck = 1;
                break;
            }
            node_decrement(&m, down);
            ++iterations;
            same |= down == up; /* rule 3, once the choice fits again */
        }
        if (stuck && !over) {
            /* Rule (2): drop what must go, then go on raising the rest into what the drops freed,
             * as the flat greedy does (Funkhouser & Séquin's "no polygons" LOD). */
            over = 1, stuck = 0;
            mb_drop_over_budget(&m);
            continue;
        }
        if (stuck || same)
            break;
    }
    r->over_budget = over;
    if (!r->truncated) {
        r->single_item = mb_single_item(&m);
    }

    /* Exact sums of the final choice (the running ones add rounding with every step). */
    double cost = 0.0, benefit = 0.0;
    uint32_t dropped = 0;
    for (uint32_t n = 0; n < (uint32_t)t->node_count; ++n) {
        if (is_choice(state[n]))
            cost += cand_cost(t, n, state[n]), benefit += cand_benefit(t, n, state[n]);
        dropped += state[n] == LOD_DROPPED;
    }
    r->cost_ms = cost, r->benefit = benefit;
    r->dropped = dropped;
    r->iterations = iterations > UINT32_MAX ? UINT32_MAX : (uint32_t)iterations;
    r->elapsed_us = (double)(hl_clock_now_ns() - t0) * 1e-3;
}
