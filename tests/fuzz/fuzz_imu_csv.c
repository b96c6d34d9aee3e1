/* Fuzz target: IMU CSV (trk_imu_csv_read, tracking/imu_csv.c), which takes a path: the bytes go to
 * a scratch file. Rows read must be finite with a unit truth quaternion (the reader's promise). */
#include "fuzz_util.h"

#include <math.h>

#include "tracking/tracking.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("fuzz-imu.csv", data, size);
    struct trk_imu_csv_row *rows = NULL;
    size_t count = 0;
    struct hl_error err;
    if (trk_imu_csv_read(path, &rows, &count, &err) == 0) {
        for (size_t i = 0; i < count; ++i) {
            const struct trk_imu_csv_row *r = &rows[i];
            const hl_quatd *q = &r->truth;
            FUZZ_CHECK(isfinite(r->t_s), "IMU row time not finite");
            FUZZ_CHECK(fabs(q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z - 1.0) < 0.1,
                       "IMU truth quaternion not unit");
        }
        trk_imu_csv_free(rows);
    }
    return 0;
}
