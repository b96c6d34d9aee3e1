/* Reader for the shared synthetic IMU CSV (data/README.md §5 "Format"):
 *   t_s,gx,gy,gz,ax,ay,az,qw,qx,qy,qz   (s, rad/s body, m/s² body, truth body-to-world w x y z)
 * Strict, because these files are the common yardstick: exact header, LF line ends, exactly 11
 * finite numbers per row with nothing after them, a truth quaternion of norm 1 ± 1e-3 (the files
 * hold 1 ± 1e-6), and a final LF (a missing one means the copy was truncated). Every error names
 * file:line. Time order is not checked here: that is the fusion's boundary (it skips and counts). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tracking/tracking.h"

#define IMU_CSV_HEADER "t_s,gx,gy,gz,ax,ay,az,qw,qx,qy,qz"

static int parse_row(const char *line, double v[11], const char *path, size_t lineno, struct hl_error *err)
{
    const char *p = line;
    for (int i = 0; i < 11; ++i) {
        if (*p == '\0' || *p == ',' || *p == ' ' || *p == '\t')
            return hl_fail(err, "%s:%zu: column %d is empty or starts with a blank", path, lineno, i + 1);
        char *end = NULL;
        errno = 0;
        v[i] = strtod(p, &end);
        if (end == p)
            return hl_fail(err, "%s:%zu: column %d is not a number", path, lineno, i + 1);
        if (!isfinite(v[i]) || errno == ERANGE)
            return hl_fail(err, "%s:%zu: column %d is not a finite number", path, lineno, i + 1);
        p = end;
        if (i < 10) {
            if (*p != ',')
                return hl_fail(err, "%s:%zu: expected ',' after column %d (11 columns)", path, lineno, i + 1);
            ++p;
        } else if (*p != '\0') {
            return hl_fail(err, "%s:%zu: trailing characters after column 11 (11 columns expected)", path, lineno);
        }
    }
    double n = sqrt(v[7] * v[7] + v[8] * v[8] + v[9] * v[9] + v[10] * v[10]);
    if (fabs(n - 1.0) > 1e-3)
        return hl_fail(err, "%s:%zu: truth quaternion norm %.6g is not 1", path, lineno, n);
    return 0;
}

int trk_imu_csv_read(const char *path, struct trk_imu_csv_row **rows_out, size_t *count_out, struct hl_error *err)
{
    *rows_out = NULL;
    *count_out = 0;
    uint64_t size = 0;
    FILE *fp = hl_file_open_read(path, &size, err); /* refuses FIFOs and devices without blocking */
    if (!fp)
        return -1;
    /* Read line by line, but the rows are kept: the same stated limit as every whole-file input. */
    if (size > hl_file_max_bytes()) {
        fclose(fp);
        return hl_fail(err, "%s: file too large: %llu bytes, more than the limit of %llu (raise it with %s)", path,
                       (unsigned long long)size, (unsigned long long)hl_file_max_bytes(), HL_FILE_MAX_BYTES_ENV);
    }
    struct trk_imu_csv_row *rows = NULL;
    size_t count = 0, cap = 0, lineno = 0;
    char line[512];
    int rc = 0;
    while (fgets(line, sizeof line, fp)) {
        ++lineno;
        size_t len = strlen(line);
        if (len == 0 || line[len - 1] != '\n') {
            if (len + 1 == sizeof line)
                rc = hl_fail(err, "%s:%zu: line longer than %zu bytes", path, lineno, sizeof line - 2);
            else
                rc = hl_fail(err, "%s:%zu: last line has no LF (truncated file?)", path, lineno);
            break;
        }
        line[--len] = '\0';
        if (len > 0 && line[len - 1] == '\r') {
            rc = hl_fail(err, "%s:%zu: CR LF line end (the format is LF only)", path, lineno);
            break;
        }
        if (lineno == 1) {
            if (strcmp(line, IMU_CSV_HEADER) != 0) {
                rc = hl_fail(err, "%s:1: header must be '%s'", path, IMU_CSV_HEADER);
                break;
            }
            continue;
        }
        double v[11];
        if ((rc = parse_row(line, v, path, lineno, err)) != 0)
            break;
        if (count == cap) {
            size_t ncap = cap ? cap * 2 : 4096;
            struct trk_imu_csv_row *nr = realloc(rows, ncap * sizeof *nr);
            if (!nr) {
                rc = hl_fail(err, "%s:%zu: out of memory", path, lineno);
                break;
            }
            rows = nr;
            cap = ncap;
        }
        struct trk_imu_csv_row *r = &rows[count++];
        r->t_s = v[0];
        r->gyro_radps = hl_v3(v[1], v[2], v[3]);
        r->accel_mps2 = hl_v3(v[4], v[5], v[6]);
        r->truth = hl_q(v[7], v[8], v[9], v[10]);
    }
    if (rc == 0 && ferror(fp))
        rc = hl_fail(err, "%s:%zu: read error", path, lineno + 1);
    if (rc == 0 && lineno == 0)
        rc = hl_fail(err, "%s:1: empty file (header expected)", path);
    if (rc == 0 && count == 0)
        rc = hl_fail(err, "%s:2: no data rows", path);
    fclose(fp);
    if (rc != 0) {
        free(rows);
        return rc;
    }
    *rows_out = rows;
    *count_out = count;
    return 0;
}

void trk_imu_csv_free(struct trk_imu_csv_row *rows) { free(rows); }
