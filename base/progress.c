#include "base/base.h"

#include <unistd.h>

void hl_progress_begin(struct hl_progress *p, const char *label, uint64_t total)
{
    p->label = label;
    p->total = total;
    p->enabled = isatty(STDERR_FILENO) && total > 0;
    p->last_permille = -1;
    hl_progress_update(p, 0);
}

void hl_progress_update(struct hl_progress *p, uint64_t done)
{
    if (!p->enabled)
        return;
    if (done > p->total)
        done = p->total;
    int permille = (int)(done * 1000 / p->total);
    if (permille == p->last_permille)
        return;
    p->last_permille = permille;
    enum { width = 30 };
    char bar[width + 1];
    int filled = permille * width / 1000;
    for (int i = 0; i < width; ++i)
        bar[i] = i < filled ? '#' : '.';
    bar[width] = '\0';
    fprintf(stderr, "\r%s [%s] %3d%% %llu/%llu", p->label, bar, permille / 10,
            (unsigned long long)done, (unsigned long long)p->total);
    fflush(stderr);
}

void hl_progress_end(struct hl_progress *p)
{
    if (!p->enabled)
        return;
    hl_progress_update(p, p->total);
    fputc('\n', stderr);
}
