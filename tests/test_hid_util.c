#include "tests/test_hid_util.h"

#include <stdio.h>
#include <string.h>

void tu_hid_print_state(struct trk_pose_source *src)
{
    struct trk_tracker_stats st;
    memset(&st, 0, sizeof st);
    char reason[768] = "";
    enum trk_health h = src->health(src, reason, sizeof reason);
    if (trk_tracker_source_stats(src, &st) != 0) {
        fprintf(stderr, "  source: no stats; health %d: %s\n", (int)h, reason);
        return;
    }
    fprintf(stderr,
            "  source: %llu reports, %llu rejected, %llu drained, %llu disconnects, %llu reconnects, %llu stalls, "
            "%llu keep-alives; %s %s\n  health %d: %s\n",
            (unsigned long long)st.reports, (unsigned long long)st.rejected, (unsigned long long)st.drained,
            (unsigned long long)st.disconnects, (unsigned long long)st.reconnects, (unsigned long long)st.stalls,
            (unsigned long long)st.keepalives, st.connected ? "connected to" : "not connected, last", st.path,
            (int)h, reason);
}
