#!/usr/bin/env bash
# Faults at the output (docs/HARD_CASES.md, "Faults"), through the program as a user runs it:
#   disk full  replay --out under tests/enospc_shim.c (LD_PRELOAD: writes under one folder
#              fail with ENOSPC after a byte budget), swept over budgets from nothing to just short of
#              the whole output: exit 1, a message naming the file and "No space left on device", no
#              temporary left, and the previous outputs intact (no new one poses as complete); the
#              soak's soak.csv and summary.json the same way;
#   symlinks   a link planted at every output name (replay's frames.csv, summary.json and PNGs, lodgen's
#              .lod, calibrate's profile, the soak's files, a bench suite's files) points at a victim
#              outside: the victim is untouched and the outputs are regular files; a link planted where
#              the program makes a folder (a bench suite's runs/ and runs-2/, and runs/ID when it runs the plan
#              itself) is refused.
set -u
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
shim=${HMDLOD_ENOSPC_SHIM:-}
shared=${HMDLOD_SHARED:-../shared}
tmp=$(mktemp -d /tmp/hmdlod-faults-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# An ASan build needs its runtime first in LD_PRELOAD.
asan=$(ldd "$bin" 2>/dev/null | awk '/libasan/ {print $3; exit}')
# full BUDGET DIR -- COMMAND...: the command with BUDGET bytes free under DIR
full() {
  local budget=$1 dir=$2; shift 3
  LD_PRELOAD="${asan:+$asan }$shim" HMDLOD_ENOSPC_DIR=$dir HMDLOD_ENOSPC_AFTER=$budget "$@"
}
strays() { find "$1" -name '*.tmp.*' | head -3; }
png_complete() { tail -c 12 "$1" | grep -q IEND; }

printf 't_s,qw,qx,qy,qz\n' >"$tmp/turn.csv"
for i in $(seq 0 200); do
  printf '%s,%s,0,%s,0\n' "$(awk "BEGIN{print $i/100}")" "$(awk "BEGIN{print cos($i/400)}")" \
    "$(awk "BEGIN{print sin($i/400)}")" >>"$tmp/turn.csv"
done
replay=(replay --trace "$tmp/turn.csv" --scene field --objects 20 --display vive --selector none --frames 20
  --render-scale 0.25 --capture 5 --quiet)
"$bin" "${replay[@]}" --out "$tmp/previous" >/dev/null 2>"$tmp/err" || { echo "FAIL: replay: $(cat "$tmp/err")"; exit 1; }

# ---- disk full ------------------------------------------------------------------------------------
if [ -z "$shim" ] || [ ! -r "$shim" ]; then
  echo "skip: disk-full cases (HMDLOD_ENOSPC_SHIM names no library; ctest sets it)"
else
  total=$(cat "$tmp/previous"/* | wc -c)
  [ "$total" -gt 1000 ] || fail "replay wrote only $total bytes"
  csv=$(wc -c <"$tmp/previous/frames.csv")
  # Nothing, mid-header of frames.csv, mid-record, half, just short of everything. The timing columns
  # make frames.csv vary by some bytes from run to run, hence the margins at the ends.
  for budget in 0 300 $((csv / 2)) $((total / 2)) $((total - 300)); do
    mkdir -p "$tmp/full"
    rm -rf "$tmp/full/run" && cp -r "$tmp/previous" "$tmp/full/run"
    full "$budget" "$tmp/full" -- "$bin" "${replay[@]}" --out "$tmp/full/run" >/dev/null 2>"$tmp/err"
    rc=$?
    [ $rc -eq 1 ] || fail "replay, $budget bytes free: exit $rc (want 1): $(cat "$tmp/err")"
    grep -Eq "(frames.csv|summary.json|frame_[0-9]+\.png): .*No space left on device" "$tmp/err" ||
      fail "replay, $budget bytes free: the message names no file and no full disk: $(cat "$tmp/err")"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "replay, $budget bytes free: more than one line: $(cat "$tmp/err")"
    cmp -s "$tmp/full/run/frames.csv" "$tmp/previous/frames.csv" &&
      cmp -s "$tmp/full/run/summary.json" "$tmp/previous/summary.json" ||
      fail "replay, $budget bytes free: frames.csv or summary.json is not the previous one"
    for png in "$tmp/full/run"/*.png; do
      png_complete "$png" || fail "replay, $budget bytes free: $png is not a whole PNG"
    done
    [ -z "$(strays "$tmp/full")" ] || fail "replay, $budget bytes free: temporaries left: $(strays "$tmp/full")"
  done
  # Without captures frames.csv is the first file written: mid-header, mid-record, at its last byte.
  for budget in 0 300 $((csv / 2)) $((csv - 300)); do
    rm -rf "$tmp/full/run" && cp -r "$tmp/previous" "$tmp/full/run"
    full "$budget" "$tmp/full" -- "$bin" "${replay[@]}" --capture 0 --out "$tmp/full/run" >/dev/null 2>"$tmp/err"
    rc=$?
    [ $rc -eq 1 ] && grep -q "frames.csv: write failed: No space left on device" "$tmp/err" ||
      fail "replay without captures, $budget bytes free: exit $rc: $(cat "$tmp/err")"
    cmp -s "$tmp/full/run/frames.csv" "$tmp/previous/frames.csv" &&
      cmp -s "$tmp/full/run/summary.json" "$tmp/previous/summary.json" ||
      fail "replay without captures, $budget bytes free: frames.csv or summary.json is not the previous one"
    [ -z "$(strays "$tmp/full")" ] || fail "replay, $budget bytes free: temporaries left: $(strays "$tmp/full")"
  done
  # Enough space: the same command succeeds under the shim (it fails only what it should).
  full $((total * 2)) "$tmp/full" -- "$bin" "${replay[@]}" --out "$tmp/full/run" >/dev/null 2>"$tmp/err" ||
    fail "replay with enough space: $(cat "$tmp/err")"
  # The soak's soak.csv (a row marked every sample) and summary.json: full at the header, after some
  # rows: exit 1 naming soak.csv, and neither file left posing as a complete soak.
  if [ -f "$shared/data/traces/corbillon-mmsys18/user1_quaternion.txt" ] && [ -f "$shared/data/imu/corbillon_user1_t30.csv" ]; then
    for budget in 0 400; do
      rm -rf "$tmp/full/soak"
      full "$budget" "$tmp/full" -- "$bin" bench soak --duration-s 2 --sample-s 0.25 --render-scale 0.25 \
        --out "$tmp/full/soak" >/dev/null 2>"$tmp/err"
      rc=$?
      [ $rc -eq 1 ] && grep -q "soak.csv: .*No space left on device" "$tmp/err" ||
        fail "bench soak, $budget bytes free: exit $rc: $(cat "$tmp/err")"
      [ ! -e "$tmp/full/soak/soak.csv" ] && [ ! -e "$tmp/full/soak/summary.json" ] ||
        fail "bench soak, $budget bytes free: an output was left: $(ls "$tmp/full/soak")"
      [ -z "$(strays "$tmp/full")" ] || fail "bench soak, $budget bytes free: temporaries left: $(strays "$tmp/full")"
    done
  else
    echo "skip: the soak's disk-full cases (no Corbillon trace or IMU stream under $shared)"
  fi
fi

# ---- planted symlinks -------------------------------------------------------------------------------
printf 'victim\n' >"$tmp/victim"
victim_ok() { [ "$(cat "$tmp/victim")" = victim ] && [ ! -L "$1" ] && [ -f "$1" ]; }
plant() { rm -f "$1" && ln -s "$tmp/victim" "$1"; }

mkdir -p "$tmp/links"
for f in frames.csv summary.json frame_000000.png frame_000005.png; do plant "$tmp/links/$f"; done
"$bin" "${replay[@]}" --out "$tmp/links" >/dev/null 2>"$tmp/err" || fail "replay over planted links: $(cat "$tmp/err")"
for f in frames.csv summary.json frame_000000.png frame_000005.png; do
  victim_ok "$tmp/links/$f" || fail "replay followed the link planted at $f"
done

if [ -f "$shared/data/meshes/suzanne.obj" ]; then
  plant "$tmp/links/s.lod"
  "$bin" lodgen "$shared/data/meshes/suzanne.obj" --levels 2 --out "$tmp/links/s.lod" >/dev/null 2>"$tmp/err" ||
    fail "lodgen: $(cat "$tmp/err")"
  victim_ok "$tmp/links/s.lod" || fail "lodgen followed the link planted at its output"
else
  echo "skip: lodgen over a planted link ($shared/data/meshes/suzanne.obj is absent)"
fi

if [ -f "$shared/data/traces/corbillon-mmsys18/user1_quaternion.txt" ] && [ -f "$shared/data/imu/corbillon_user1_t30.csv" ]; then
  mkdir -p "$tmp/links/soak"
  for f in soak.csv summary.json; do plant "$tmp/links/soak/$f"; done
  "$bin" bench soak --duration-s 1 --render-scale 0.25 --out "$tmp/links/soak" >/dev/null 2>"$tmp/err" ||
    fail "bench soak over planted links: $(cat "$tmp/err")"
  for f in soak.csv summary.json; do
    victim_ok "$tmp/links/soak/$f" || fail "bench soak followed the link planted at $f"
  done
fi

plant "$tmp/links/cost.json"
"$bin" calibrate --quick --render-scale 0.25 --out "$tmp/links/cost.json" >/dev/null 2>"$tmp/err" ||
  fail "calibrate: $(cat "$tmp/err")"
victim_ok "$tmp/links/cost.json" || fail "calibrate followed the link planted at its profile"

if [ -f "$shared/data/traces/corbillon-mmsys18/user1_quaternion.txt" ]; then
  suite=(bench --tiny --only 't1-*')
  mkdir -p "$tmp/suite"
  for f in suite.txt still-head.csv; do plant "$tmp/suite/$f"; done
  plant "$tmp/plan.txt"
  "$bin" "${suite[@]}" --plan "$tmp/plan.txt" --out "$tmp/suite" >/dev/null 2>"$tmp/err" ||
    fail "bench --plan over planted links: $(cat "$tmp/err")"
  for f in "$tmp/suite/suite.txt" "$tmp/suite/still-head.csv" "$tmp/plan.txt"; do
    victim_ok "$f" || fail "bench followed the link planted at $f"
  done
  # Folders the suite makes: a link at runs/ or at runs/ID is refused before anything is written through it.
  id=$(grep -o "suite/runs/[^' ]*" "$tmp/plan.txt" | head -1 | sed 's|.*/||') # the first run
  mkdir -p "$tmp/elsewhere" "$tmp/suite2" "$tmp/suite3/runs"
  ln -s "$tmp/elsewhere" "$tmp/suite2/runs"
  "$bin" "${suite[@]}" --plan "$tmp/plan2.txt" --out "$tmp/suite2" >/dev/null 2>"$tmp/err"
  rc=$?
  [ $rc -eq 1 ] && grep -q "suite2/runs: is a symbolic link" "$tmp/err" ||
    fail "bench with runs/ a planted link: exit $rc: $(cat "$tmp/err")"
  if [ -n "$id" ]; then
    ln -s "$tmp/elsewhere" "$tmp/suite3/runs/$id"
    "$bin" "${suite[@]}" --out "$tmp/suite3" >/dev/null 2>"$tmp/err"
    rc=$?
    [ $rc -eq 1 ] && grep -q "runs/$id: is a symbolic link" "$tmp/err" ||
      fail "bench with runs/$id a planted link: exit $rc: $(cat "$tmp/err")"
  else
    fail "bench --plan names no run"
  fi
  # the second round's folder, runs-2/, likewise
  mkdir -p "$tmp/suite4"
  ln -s "$tmp/elsewhere" "$tmp/suite4/runs-2"
  "$bin" "${suite[@]}" --plan "$tmp/plan4.txt" --out "$tmp/suite4" >/dev/null 2>"$tmp/err"
  rc=$?
  [ $rc -eq 1 ] && grep -q "suite4/runs-2: is a symbolic link" "$tmp/err" ||
    fail "bench with runs-2/ a planted link: exit $rc: $(cat "$tmp/err")"
  [ -z "$(ls -A "$tmp/elsewhere")" ] || fail "something was written through a planted folder link"
else
  echo "skip: the bench suite's links (no Corbillon traces under $shared)"
fi

echo "fault tests: $failures failed"
[ $failures -eq 0 ]
