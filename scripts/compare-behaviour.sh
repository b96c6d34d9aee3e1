#!/usr/bin/env bash
# Behaviour check for refactors: records what a build of hmdlod computes, in the columns that do not
# follow measured time, and compares two such records byte for byte (docs/testing.md "Refactors").
#
#   scripts/compare-behaviour.sh record HMDLOD DIR   run HMDLOD (a built program) and keep its
#                                                    deterministic output in DIR (made; must not exist)
#   scripts/compare-behaviour.sh compare DIR_A DIR_B  exit 0 when both records are identical,
#                                                    1 (with a diff) otherwise
#
# What a record holds (run from the checkout, with ../shared beside it; HMDLOD_SHARED overrides):
#   - replay of Corbillon user1 through field, auditorium, domes and tests/scenes/real-meshes.json with
#     none, static and reddy, and of EDVAM participant 2 on field with --gaze tracked: every
#     frames.csv column before the machine-dependent ones (acuity_us … minor_faults; docs/replay-output.md),
#     image metrics included (--reference), and summary.json without its timing and memory fields;
#   - bench --quick: every table's deterministic columns (those DIR/deterministic.txt lists).
# fs, mb and feedback react to measured frame times and are not compared. FRAMES (default 300) and
# REFERENCE_EVERY (default 30) set the replays' length and image comparisons; QUICK_BENCH=0 skips
# the bench. Each record analyses the built-in chains afresh in its own cache (DIR/lodcache), so the
# analysis is compared too (through its effect on the levels chosen).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
    sed -n '4,8p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
}

# frames.csv without the timing columns: everything before acuity_us.
cut_timing() {
    awk -F, 'NR == 1 { n = NF; for (i = 1; i <= NF; i++) if ($i == "acuity_us") { n = i - 1; break } }
             { line = $1; for (i = 2; i <= n; i++) line = line "," $i; print line }' "$1"
}

# summary.json without the fields that follow wall-clock time or the process's memory.
strip_summary() {
    python3 - "$1" <<'EOF'
import json, re, sys
timing = re.compile(r"^(frame_ms|draw_ms|acuity_us|select_us|optimizer_us|vm_|deadline_met|minor_faults)")
with open(sys.argv[1]) as f:
    s = json.load(f)
s = {k: v for k, v in s.items() if not timing.match(k)}
json.dump(s, sys.stdout, indent=1, sort_keys=True)
print()
EOF
}

# The bench tables' deterministic columns: deterministic.txt lists "table.csv: col, col, …".
strip_bench() {
    local bench=$1 out=$2
    python3 - "$bench" "$out" <<'EOF'
import csv, os, sys
bench, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
with open(os.path.join(bench, "deterministic.txt")) as f:
    lines = [l.rstrip("\n") for l in f if l.strip() and not l.startswith("#")]
with open(os.path.join(out, "deterministic.txt"), "w") as f:
    f.write("\n".join(lines) + "\n")
for line in lines:
    name, _, cols = line.partition(":")
    name = name.strip()
    cols = [c.strip() for c in cols.split(",") if c.strip()]
    with open(os.path.join(bench, name), newline="") as f:
        rows = list(csv.reader(f))
    head = rows[0]
    missing = [c for c in cols if c not in head]
    if missing:
        sys.exit(f"{name}: deterministic columns not in the table: {missing}")
    if not cols:
        continue
    # The row's name (first column) and its deterministic columns, on the rows marked deterministic.
    idx = [0] + [head.index(c) for c in cols if head.index(c) != 0]
    flag = head.index("deterministic") if "deterministic" in head else None
    with open(os.path.join(out, name), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        for n, r in enumerate(rows):
            if n > 0 and flag is not None and (flag >= len(r) or r[flag] != "1"):
                continue
            w.writerow([r[i] if i < len(r) else "" for i in idx])
EOF
}

record() {
    local exe dir shared frames ref
    exe=$(realpath "$1")
    dir=$2
    [ -x "$exe" ] || { echo "compare-behaviour: $1: not an executable" >&2; exit 2; }
    [ -e "$dir" ] && { echo "compare-behaviour: $dir: exists (a record goes into a new folder)" >&2; exit 2; }
    shared=${HMDLOD_SHARED:-../shared}
    frames=${FRAMES:-300}
    ref=${REFERENCE_EVERY:-30}
    local user1=$shared/data/traces/corbillon-mmsys18/user1_quaternion.txt
    local edvam=$shared/data/traces/edvam-gaze/participant2.csv
    for f in "$user1" "$edvam" "$shared/data/meshes/stanford-bunny.obj"; do
        [ -f "$f" ] || { echo "compare-behaviour: $f: missing (the shared data folder is needed)" >&2; exit 2; }
    done
    mkdir -p "$dir/raw" "$dir/det"
    dir=$(realpath "$dir")
    export HMDLOD_CACHE_DIR=$dir/lodcache
    echo "program: $exe" >"$dir/det/what.txt"
    echo "frames $frames, reference every $ref" >>"$dir/det/what.txt"
    run_case() { # id, replay arguments…
        local id=$1
        shift
        echo "== $id" >&2
        "$exe" replay "$@" --frames "$frames" --reference "$ref" --out "$dir/raw/$id" --quiet
        cut_timing "$dir/raw/$id/frames.csv" >"$dir/det/$id.frames.csv"
        strip_summary "$dir/raw/$id/summary.json" >"$dir/det/$id.summary.json"
        echo "replay $* --frames $frames --reference $ref" >>"$dir/det/what.txt"
    }
    local scene sel
    for scene in field auditorium domes tests/scenes/real-meshes.json; do
        for sel in none static reddy; do
            run_case "user1-$(basename "$scene" .json)-$sel" --trace "$user1" --scene "$scene" --display vive \
                --selector "$sel"
        done
    done
    for sel in none static reddy; do
        run_case "edvam2-field-tracked-$sel" --trace "$edvam" --scene field --display vive --selector "$sel" \
            --gaze tracked
    done
    if [ "${QUICK_BENCH:-1}" != 0 ]; then
        echo "== bench --quick" >&2
        HMDLOD_SHARED=$shared "$exe" bench --quick --out "$dir/raw/bench" >"$dir/raw/bench.log"
        strip_bench "$dir/raw/bench" "$dir/det/bench"
        echo "bench --quick: the deterministic columns of every table" >>"$dir/det/what.txt"
    fi
    echo "compare-behaviour: recorded $(find "$dir/det" -type f | wc -l) files in $dir/det" >&2
}

compare() {
    local a=$1/det b=$2/det
    [ -d "$a" ] && [ -d "$b" ] || { echo "compare-behaviour: both arguments must be records" >&2; exit 2; }
    # what.txt names the program; everything else must match byte for byte.
    if diff -r -x what.txt "$a" "$b"; then
        echo "compare-behaviour: identical ($(find "$a" -type f ! -name what.txt | wc -l) files)"
    else
        echo "compare-behaviour: DIFFERENT (above)" >&2
        exit 1
    fi
}

case "${1:-}" in
record) [ $# -eq 3 ] || usage; record "$2" "$3" ;;
compare) [ $# -eq 3 ] || usage; compare "$2" "$3" ;;
*) usage ;;
esac
