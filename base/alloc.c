/* Allocation failures inside libraries that cannot report them: cJSON returns NULL from a parse both
 * for bad text and for a failed allocation, so its loaders hand it these (cJSON_InitHooks) and tell
 * "out of memory" from "not valid JSON" by the count (docs/HARD_CASES.md, "Faults"). */
#include "base/base.h"

#include <stdlib.h>

static uint64_t failures; /* updated atomically: loaders may run on several threads */

void *hl_lib_malloc(size_t n)
{
    void *p = malloc(n);
    if (!p)
        __atomic_add_fetch(&failures, 1, __ATOMIC_RELAXED);
    return p;
}

void hl_lib_free(void *p) { free(p); }

uint64_t hl_lib_alloc_failures(void) { return __atomic_load_n(&failures, __ATOMIC_RELAXED); }
