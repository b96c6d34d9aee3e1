#!/usr/bin/env bash
# hmdlod bench soak, a few seconds of it (the hour is a benchmark, docs/bench.md "Soak"): exit 0,
# soak.csv with its header and one filled row per second, every field a finite number, counters that
# grow, summary.json valid with finite figures, the table's verdict rows, and no temporary left.
# Not a performance check. Skips (77) when the shared trace or IMU stream or python3 is absent.
set -u
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
shared=${HMDLOD_SHARED:-../shared}
skip() { echo "SKIP: $*"; exit 77; }
[ -f "$shared/data/traces/corbillon-mmsys18/user1_quaternion.txt" ] || skip "no Corbillon traces under $shared"
[ -f "$shared/data/imu/corbillon_user1_t30.csv" ] || skip "no IMU streams under $shared"
command -v python3 >/dev/null || skip "python3 is not installed"
tmp=$(mktemp -d /tmp/hmdlod-soak-XXXXXX)
trap 'rm -rf "$tmp"' EXIT

"$bin" bench soak --duration-s 4 --sample-s 1 --out "$tmp/out" >"$tmp/stdout" 2>"$tmp/stderr"
rc=$?
[ $rc -eq 0 ] || { echo "FAIL: bench soak exit $rc: $(cat "$tmp/stderr")"; exit 1; }
for row in "RSS kB" "resident kB in [heap] mapping" "resident kB in anonymous" "resident kB in file-backed" "open fds" "frame ms median" "CPU ms per frame median" "tracker reports/s" "fusion output"; do
  grep -qF "| $row" "$tmp/stdout" || { echo "FAIL: the table lacks the row '$row'"; cat "$tmp/stdout"; exit 1; }
done
grep -qE "^- (machine|commit|renderer|command):" "$tmp/stdout" || { echo "FAIL: no bench context lines"; exit 1; }
ls "$tmp/out" | grep -q '\.tmp\.' && { echo "FAIL: a temporary was left: $(ls "$tmp/out")"; exit 1; }
python3 - "$tmp/out" <<'PY'
import csv, json, math, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/soak.csv")))
want = ["t_s", "rss_kib", "heap_kib", "open_fds", "frames", "reports", "missed_slots", "frame_ms_mean", "cpu_ms_mean",
        "triangles_mean", "fusion_nonfinite", "trace_loops", "imu_loops", "heap_free_kib", "heap_map_kib",
        "anon_map_kib", "file_map_kib", "mappings"]
fails = []
if not rows or list(rows[0].keys()) != want:
    fails.append("soak.csv header is %s" % (list(rows[0].keys()) if rows else "missing"))
if not 3 <= len(rows) <= 6:
    fails.append("%d rows for 4 s sampled every 1 s" % len(rows))
for i, r in enumerate(rows):
    for k in want:
        try:
            v = float(r[k])
        except (TypeError, ValueError):
            fails.append("row %d: %s = %r is not a number" % (i + 1, k, r[k])); continue
        if not math.isfinite(v):
            fails.append("row %d: %s = %r is not finite" % (i + 1, k, r[k]))
    if fails:
        break
    if float(r["rss_kib"]) <= 0 or float(r["open_fds"]) <= 0 or float(r["frames"]) <= 0:
        fails.append("row %d: RSS, fds or frames not positive: %s" % (i + 1, r))
    # the split by mapping covers what is resident: its parts sum to about the RSS (read a moment apart)
    parts = float(r["heap_map_kib"]) + float(r["anon_map_kib"]) + float(r["file_map_kib"])
    if not (float(r["mappings"]) > 10 and float(r["file_map_kib"]) > 0 and 0.8 * float(r["rss_kib"]) <= parts <= 1.05 * float(r["rss_kib"])):
        fails.append("row %d: resident by mapping %.0f kB (%s maps) against RSS %s kB" % (i + 1, parts, r["mappings"], r["rss_kib"]))
    if float(r["fusion_nonfinite"]) != 0:
        fails.append("row %d: non-finite fusion output" % (i + 1))
if not fails:
    for a, b in zip(rows, rows[1:]):
        for k in ("t_s", "frames", "reports"):
            if not float(b[k]) > float(a[k]):
                fails.append("%s does not grow between rows: %s then %s" % (k, a[k], b[k]))
    # the tracker runs at 1 kHz: about 1000 reports per second of t_s (loose: a loaded machine)
    rate = float(rows[-1]["reports"]) / float(rows[-1]["t_s"])
    if not 500 <= rate <= 1100:
        fails.append("tracker fed %.0f reports/s, not about 1000" % rate)
s = json.load(open(d + "/summary.json"))
for k in ("frames", "reports", "rss_start_kib", "rss_end_kib", "fds_start", "fds_end", "rate_hz",
          "frame_ms_median_ratio", "cpu_ms_median_ratio"):
    if not isinstance(s.get(k), (int, float)) or not math.isfinite(s[k]) or s[k] <= 0:
        fails.append("summary.json: %s = %r" % (k, s.get(k)))
for part in ("first", "last"):
    for k in ("frame_ms_median", "frame_ms_p99", "cpu_ms_median", "cpu_ms_p99", "reports_per_s"):
        v = s.get(part, {}).get(k)
        if not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
            fails.append("summary.json: %s.%s = %r" % (part, k, v))
if s.get("fusion_nonfinite") != 0:
    fails.append("summary.json: fusion_nonfinite = %r" % s.get("fusion_nonfinite"))
if fails:
    print("FAIL: " + "\nFAIL: ".join(fails))
    sys.exit(1)
print("soak smoke: %d rows, %d frames, %d reports" % (len(rows), s["frames"], s["reports"]))
PY
