#!/usr/bin/env bash
# hmdlod bench's suite end to end (docs/bench.md).
#   tiny:  the --tiny plan serially (2 alternated rounds, the default), and as a plan under
#          `parallel --will-cite -j2` then --merge; the merged report's deterministic columns
#          (deterministic.txt) must equal the serial run's, and each round's triangles the first
#          round's; every table heading in report.md; every plot a PNG; missing runs and rounds and bad
#          arguments give one message and exit 1.
#   quick: `hmdlod bench --quick --repeats 1 --out DIR`: exit 0, every table heading, the PNGs. One
#          round keeps CI's time; the rounds themselves are the tiny mode's.
# Skips (77) when the shared traces, GNU parallel, gnuplot or python3 are absent.
set -u
mode=${1:-tiny}
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
shared=${HMDLOD_SHARED:-../shared}
skip() { echo "SKIP: $*"; exit 77; }
[ -f "$shared/data/traces/corbillon-mmsys18/user1_quaternion.txt" ] || skip "no Corbillon traces under $shared"
command -v gnuplot >/dev/null || skip "gnuplot is not installed (scripts/setup.sh installs gnuplot-nox)"
tmp=$(mktemp -d /tmp/hmdlod-bench-suite-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

headings=("## Table 1: Funkhouser's Table 1 on real traces" "## Table 2: speed against error"
  "## Table 2b: at equal fSSIM" "## Table 3: Reddy's study on field" "## Table 3b: per display"
  "## Table 3c: the two frequency readings" "## Table 3e: the two visibility criteria" "## Table 3f: the two visibility criteria"
  "## Table 4: Nirenstein's measurements" "## Table 4b: hierarchy simplifications"
  "## Table 5: Mason–Blake's comparison on domes" "## Table 6: the cost model" "## Table 7: foveated layers")

check_report() { # DIR: headings, CSVs, PNGs
  local dir=$1
  [ -f "$dir/report.md" ] || { fail "$dir/report.md missing"; return; }
  for h in "${headings[@]}"; do
    grep -qF -- "$h" "$dir/report.md" || fail "$dir/report.md lacks the heading '$h'"
  done
  grep -q -- "- renderer: " "$dir/report.md" || fail "$dir/report.md names no renderer"
  for t in t1_funkhouser t2_speed_error t3_reddy_speedup t4_nirenstein t5_mason_blake t6_cost_model t7_layers; do
    [ -s "$dir/$t.csv" ] || fail "$dir/$t.csv missing or empty"
  done
  local n=0
  for gp in "$dir"/plots/*.gp; do
    local png=${gp%.gp}.png
    n=$((n + 1))
    [ -s "$png" ] || { fail "$png missing"; continue; }
    [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || fail "$png is not a PNG"
  done
  [ $n -ge 7 ] || fail "$dir/plots: $n plot scripts, want at least 7"
}

if [ "$mode" = quick ]; then
  "$bin" bench --quick --repeats 1 --out "$tmp/quick" >"$tmp/quick.out" 2>"$tmp/quick.err" || {
    fail "bench --quick: exit $?: $(tail -5 "$tmp/quick.err")"
    exit 1
  }
  check_report "$tmp/quick"
  grep -qF "## Table 1" "$tmp/quick.out" || fail "bench --quick printed no Table 1 on stdout"
  grep -q -- "- timing: one round of every run" "$tmp/quick/report.md" || fail "the report does not say it had one round"
  [ $failures -eq 0 ] && echo "bench --quick: report and plots complete"
  exit $((failures > 0))
fi

command -v parallel >/dev/null || skip "GNU parallel is not installed (scripts/setup.sh installs it)"
command -v python3 >/dev/null || skip "python3 is not installed"

# serial
"$bin" bench --tiny --out "$tmp/serial" >"$tmp/serial.out" 2>"$tmp/serial.err" ||
  fail "serial --tiny: exit $?: $(tail -3 "$tmp/serial.err")"
check_report "$tmp/serial"
# the plan under GNU parallel, then the merge
"$bin" bench --tiny --plan "$tmp/plan.txt" --out "$tmp/par" 2>"$tmp/plan.err" ||
  fail "--plan: exit $?: $(cat "$tmp/plan.err")"
lines=$(wc -l <"$tmp/plan.txt")
runs=$(($(wc -l <"$tmp/serial/runs.csv") - 1))
[ "$runs" -ge 20 ] || fail "the tiny plan has $runs runs, want ≥ 20"
[ "$lines" -eq $((2 * runs)) ] || fail "the tiny plan has $lines lines, want 2 rounds × $runs runs"
[ "$(grep -c -- "--out $tmp/par/runs-2/" "$tmp/plan.txt")" -eq "$runs" ] || fail "the plan's second round does not write runs-2/"
[ -d "$tmp/par/runs" ] && [ -d "$tmp/par/runs-2" ] && [ -z "$(find "$tmp/par/runs" "$tmp/par/runs-2" -mindepth 1)" ] ||
  fail "--plan ran runs itself"
parallel --will-cite -j2 <"$tmp/plan.txt" >"$tmp/parallel.out" 2>&1 || fail "parallel: $(tail -3 "$tmp/parallel.out")"
"$bin" bench --merge "$tmp/par" >"$tmp/merge.out" 2>"$tmp/merge.err" || fail "--merge: exit $?: $(cat "$tmp/merge.err")"
check_report "$tmp/par"
# how the runs shared the machine, from their wall-clock spans: the serial run says serial, the plan
# under parallel -j2 marks its timing columns as from parallel runs
grep -q -- "- timing: serial" "$tmp/serial/report.md" || fail "the serial report does not say its runs were serial"
grep -q -- "- timing: 2 alternated rounds of every run" "$tmp/serial/report.md" || fail "the report does not say it had 2 rounds"
[ "$(ls "$tmp/serial/runs")" = "$(ls "$tmp/serial/runs-2")" ] || fail "the serial run's second round does not hold every run"
# the rounds are real replays of the same configuration: the deterministic selectors draw the same
# triangles on every frame in both rounds
python3 - "$tmp/serial" <<'EOF' || fail "a deterministic run drew other triangles in its second round"
import csv, json, os, sys
d, compared, bad = sys.argv[1], 0, 0
for run in sorted(os.listdir(f"{d}/runs")):
    sel = json.load(open(f"{d}/runs/{run}/summary.json")).get("selector")
    if sel not in ("none", "static", "reddy"):
        continue
    cols = ("triangles_per_eye", "lod0", "lod1", "lod2", "lod3")
    a = [[r[c] for c in cols] for r in csv.DictReader(open(f"{d}/runs/{run}/frames.csv"))]
    b = [[r[c] for c in cols] for r in csv.DictReader(open(f"{d}/runs-2/{run}/frames.csv"))]
    compared += 1
    if a != b:
        print(f"{run}: triangles differ between the rounds"); bad += 1
print(f"{compared} deterministic runs compared across rounds, {bad} differ")
sys.exit(1 if bad or compared < 10 else 0)
EOF
grep -q -- "- timing: \*\*from parallel runs\*\*" "$tmp/par/report.md" ||
  fail "the report of the plan under parallel -j2 does not mark its timings as from parallel runs"
# deterministic columns: merged (parallel) against serial
python3 - "$tmp/serial" "$tmp/par" <<'EOF' || fail "deterministic columns differ between the serial and the parallel run"
import csv, sys
a, b = sys.argv[1], sys.argv[2]
compared, bad = 0, 0
for line in open(f"{a}/deterministic.txt"):
    if line.startswith("#") or ":" not in line:
        continue
    name, cols = line.split(":", 1)
    cols = [c for c in cols.strip().split(",") if c]
    ra = list(csv.DictReader(open(f"{a}/{name}")))
    rb = list(csv.DictReader(open(f"{b}/{name}")))
    if len(ra) != len(rb):
        print(f"{name}: {len(ra)} rows serial, {len(rb)} merged"); bad += 1; continue
    for i, (x, y) in enumerate(zip(ra, rb)):
        if x.get("deterministic") != "1":
            continue
        for c in cols:
            compared += 1
            if x[c] != y[c]:
                print(f"{name} row {i + 2} {c}: serial {x[c]!r}, merged {y[c]!r}"); bad += 1
print(f"{compared} deterministic cells compared, {bad} differ")
sys.exit(1 if bad or compared < 20 else 0)
EOF

# --plan without --out: the folder is FILE.d
"$bin" bench --tiny --only 't5-*' --plan "$tmp/p5.txt" 2>"$tmp/err" && [ -f "$tmp/p5.txt.d/suite.txt" ] &&
  grep -q -- "--out $tmp/p5.txt.d/runs/t5-" "$tmp/p5.txt" || fail "--plan without --out: $(cat "$tmp/err")"

# without gnuplot on PATH: the tables still come out and the report says why there are no images
PATH=/nonexistent "$bin" bench --merge "$tmp/par" --out "$tmp/nognuplot" >/dev/null 2>"$tmp/err" ||
  fail "--merge without gnuplot: exit $?: $(cat "$tmp/err")"
grep -q "gnuplot is not on PATH" "$tmp/nognuplot/report.md" && [ -s "$tmp/nognuplot/t1_funkhouser.csv" ] &&
  [ -s "$tmp/nognuplot/plots/t6_cost.gp" ] && ! ls "$tmp/nognuplot/plots/"*.png >/dev/null 2>&1 ||
  fail "--merge without gnuplot: the report does not say so, or the tables or scripts are missing"

# a partial merge: one run folder gone
cp -r "$tmp/par" "$tmp/partial"
gone=$(ls "$tmp/partial/runs" | head -1)
rm -rf "$tmp/partial/runs/$gone"
"$bin" bench --merge "$tmp/partial" >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -q "1 of $lines replays missing ($gone)" "$tmp/err" || fail "merge with $gone missing: exit $rc: $(cat "$tmp/err")"
"$bin" bench --merge "$tmp/partial" --partial >/dev/null 2>"$tmp/err" || fail "--partial: exit $?: $(cat "$tmp/err")"
grep -qF "1 run(s) or round(s) missing: $gone;" "$tmp/partial/report.md" || fail "the partial report does not name $gone"
grep -qF "runs: $((runs - 1)) of $runs, 2 round(s) each: $((lines - 1)) of $lines replays" "$tmp/partial/report.md" ||
  fail "the partial report does not count the runs and replays present"
# a round missing: named with its round
cp -r "$tmp/par" "$tmp/noround"
rm -rf "$tmp/noround/runs-2/$gone"
"$bin" bench --merge "$tmp/noround" >/dev/null 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] && grep -qF "1 of $lines replays missing ($gone (round 2))" "$tmp/err" ||
  fail "merge with round 2 of $gone missing: exit $rc: $(cat "$tmp/err")"
# the union of two folders: the missing run taken from the other
"$bin" bench --merge "$tmp/partial" "$tmp/par" --out "$tmp/union" >/dev/null 2>"$tmp/err" ||
  fail "merge of two folders: exit $?: $(cat "$tmp/err")"
grep -q "runs: $runs of $runs" "$tmp/union/report.md" || fail "the union does not hold every run"

# bad arguments: one message, exit 1
expect_error() { # WHAT REGEX -- COMMAND...
  local what=$1 pattern=$2; shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"; local rc=$?
  [ $rc -eq 1 ] || { fail "$what: exit $rc (want 1): $(cat "$tmp/err")"; return; }
  grep -Eq -- "$pattern" "$tmp/err" || fail "$what: stderr does not match /$pattern/: $(cat "$tmp/err")"
}
expect_error "unknown option" "unknown option '--fast'" -- "$bin" bench --fast --out "$tmp/x"
expect_error "no --out" "--out DIR is required" -- "$bin" bench --quick
mkdir -p "$tmp/empty"
expect_error "merge of a folder that is no suite" "empty/suite.txt: cannot read" -- "$bin" bench --merge "$tmp/empty"
mkdir -p "$tmp/noruns/runs" && cp "$tmp/par/suite.txt" "$tmp/noruns/"
expect_error "merge of a folder with no runs" "no runs found" -- "$bin" bench --merge "$tmp/noruns"
touch "$tmp/file"
expect_error "unwritable --out" "--out .*file/sub: cannot create the folder" -- "$bin" bench --tiny --out "$tmp/file/sub"
expect_error "--only matching nothing" "matches no run id" -- "$bin" bench --tiny --only 'zz*' --out "$tmp/only"
expect_error "--partial without --merge" "--partial goes with --merge" -- "$bin" bench --partial --out "$tmp/x"
expect_error "--repeats 0" "--repeats '0': want a whole number 1 ... 9" -- "$bin" bench --tiny --repeats 0 --out "$tmp/x"
expect_error "--repeats 2x" "--repeats '2x'" -- "$bin" bench --tiny --repeats 2x --out "$tmp/x"
expect_error "--repeats with --merge" "--merge takes run folders" -- "$bin" bench --merge "$tmp/par" --repeats 2
sed 's/^repeats .*/repeats 10/' "$tmp/par/suite.txt" >"$tmp/noruns/suite.txt"
expect_error "suite.txt with 10 rounds" "suite.txt:[0-9]+: repeats '10': want 1" -- "$bin" bench --merge "$tmp/noruns"

[ $failures -eq 0 ] && echo "bench suite: serial and parallel agree on $runs runs; merge, partial and errors as documented"
exit $((failures > 0))
