#!/usr/bin/env bash
# hmdlod live as a user meets it, under Xvfb (PLATFORM.md §3): the issue's acceptance command (120
# frames, the summary's present intervals, a PNG of the window), a session stopped by SIGINT (the
# summary printed, the head trace complete and replayable), --list-monitors, and a distorted DK2
# capture whose lens border is black and whose centre is not. Skips (77) only when Xvfb is absent.
set -u
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
command -v Xvfb >/dev/null || { echo "skip: Xvfb is absent (apt-get install xvfb xauth)"; exit 77; }
tmp=$(mktemp -d /tmp/hmdlod-live-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
here=$(cd "$(dirname "$0")" && pwd)
# Each session gets its own Xvfb, known to answer before the session starts and never reset between
# the session's connections (tests/with_xvfb.sh): xvfb-run -a now and then let a client meet no
# server, or a resetting one ("Failed to open display").
xvfb() { "$here/with_xvfb.sh" "$@"; }
# probe FILE POINTS...: tests/png_probe.py's lines (RGB at points, distinct colours per half); empty
# (and a note) without python3.
probe() {
  command -v python3 >/dev/null || { echo "note: no python3: pixel checks of $1 skipped" >&2; return 0; }
  python3 "$here/png_probe.py" "$@"
}
# rendered FILE MIN: both halves (both eyes) hold at least MIN distinct colours: something was drawn.
rendered() {
  local out; out=$(probe "$1") || return 1
  [ -z "$out" ] && return 0
  awk -v m="$2" '/^half/ { if ($2 < m) bad = 1; n++ } END { exit !(n == 2 && !bad) }' <<<"$out"
}

# png_size FILE: "W H" from the IHDR chunk, or nothing when FILE is not a PNG.
png_size() {
  [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || return 1
  od -An -tu1 -j16 -N8 "$1" | awk '{ print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8 }'
}

# The acceptance command.
xvfb "$bin" live --device none --display vive --scene auditorium --frames 120 --capture "$tmp/live.png" \
  >"$tmp/out" 2>"$tmp/err"
rc=$?
[ $rc -eq 0 ] || fail "acceptance: exit $rc: $(tail -3 "$tmp/err")"
grep -Eq "present interval ms: median [0-9.]+ +p99 [0-9.]+ +stddev [0-9.]+" "$tmp/out" \
  || fail "acceptance: no present intervals in the summary: $(cat "$tmp/out")"
grep -Eq "frames 120, missed [0-9]+" "$tmp/out" || fail "acceptance: not 120 frames: $(cat "$tmp/out")"
size=$(png_size "$tmp/live.png") || fail "acceptance: $tmp/live.png is not a PNG"
window=$(grep -o "window [0-9]* x [0-9]*" "$tmp/out" | awk '{ print $2, $4 }')
[ "$size" = "$window" ] || fail "acceptance: PNG is '$size', the window '$window'"
rendered "$tmp/live.png" 50 || fail "acceptance: the PNG does not show two rendered eye views: $(probe "$tmp/live.png")"
stray=$(ls "$tmp" | grep -v -E '^(out|err|live\.png)$')
[ -z "$stray" ] || fail "acceptance: files left beside the capture: $stray"

# Esc/close/SIGINT: a session without --frames stopped by SIGINT prints its summary and leaves a
# complete head trace (no .partial) that replay reads back. The signal goes once the session has
# recorded two rows (a header and two lines in head.csv's temporary: rows are flushed per frame), not
# after a fixed time, which a loaded machine can overrun; the wait is bounded (120 s × the time scale).
polls=$(awk -v s="${HMDLOD_TEST_TIME_SCALE:-1}" 'BEGIN { s += 0; if (s < 1) s = 1; printf "%d", 1200 * s }')
xvfb bash -c '"$0" live --device none --display dk2 --scene field --render-scale 0.25 --window-size 320x180 \
    --yaw-degps 30 --record "$1/head.csv" --log "$1/frames.csv" --quiet >"$1/int.out" 2>"$1/int.err" & pid=$!
  for _ in $(seq 1 "$2"); do
    [ "$(cat "$1"/head.csv.tmp.* 2>/dev/null | wc -l)" -ge 3 ] && break
    kill -0 $pid 2>/dev/null || break
    sleep 0.1
  done
  kill -INT $pid; wait $pid' \
  "$bin" "$tmp" "$polls"
rc=$?
[ $rc -eq 0 ] || fail "SIGINT: exit $rc: $(tail -3 "$tmp/int.err")"
grep -q "interrupted" "$tmp/int.err" || fail "SIGINT: no 'interrupted' note: $(cat "$tmp/int.err")"
grep -q "present interval ms" "$tmp/int.out" || fail "SIGINT: no summary: $(cat "$tmp/int.out")"
[ -e "$tmp/head.csv" ] && [ ! -e "$tmp/head.csv.partial" ] && [ -z "$(find "$tmp" -maxdepth 1 -name '*.tmp.*')" ] || fail "SIGINT: the head trace is missing or partial"
rows=$(($(wc -l <"$tmp/head.csv") - 1))
frames=$(grep -o "frames [0-9]*" "$tmp/int.out" | awk '{ print $2 }')
[ "$rows" -ge 2 ] && [ "$rows" = "$frames" ] || fail "SIGINT: $rows trace rows for $frames frames"
[ "$(($(wc -l <"$tmp/frames.csv") - 1))" = "$frames" ] && [ ! -e "$tmp/frames.csv.partial" ] \
  || fail "SIGINT: the per-frame log does not have one complete row per frame"
head -1 "$tmp/frames.csv" | grep -q "^frame,t_s,frame_ms,distortion_ms,present_interval_ms," || fail "SIGINT: log header"
# The scripted yaw turns about +Y at 30 deg/s: the last row's quaternion has |qy| > 0.
awk -F, 'END { exit !($4 > 0.01 || $4 < -0.01) }' "$tmp/head.csv" || fail "SIGINT: the head did not turn"
"$bin" replay --trace "$tmp/head.csv" --scene field --render-scale 0.25 --selector none --quiet --out "$tmp/re" \
  2>"$tmp/re.err" || fail "the recorded head trace does not replay: $(cat "$tmp/re.err")"

# Monitors: Xvfb's one screen, and the note on non-desktop headsets.
out=$(xvfb "$bin" live --list-monitors 2>&1) || fail "--list-monitors: $out"
grep -q "non-desktop" <<<"$out" || fail "--list-monitors: no non-desktop note: $out"
grep -Eq "^0 +[^ ]+ +[0-9]+x[0-9]+" <<<"$out" || fail "--list-monitors: no monitor 0: $out"
xvfb "$bin" live --device none --monitor 5 --frames 2 >/dev/null 2>"$tmp/err"
[ $? -eq 1 ] && grep -q "there are 1 monitors" "$tmp/err" || fail "--monitor 5: $(cat "$tmp/err")"

# Foveated layers live (issue 32's acceptance): the distortion pass composites them — the session
# runs, the capture is drawn in both eyes with the lens border black (test_layers checks the pass's
# pixels against the plain frame's and the composite's).
xvfb "$bin" live --device none --display dk2 --scene auditorium --foveation fixed --frames 20 --render-scale 0.5 \
  --window-size 480x270 --capture "$tmp/dk2-fov.png" --quiet >"$tmp/out" 2>"$tmp/err" || fail "dk2 foveated: $(cat "$tmp/err")"
[ "$(png_size "$tmp/dk2-fov.png")" = "480 270" ] || fail "dk2 foveated: capture size"
rendered "$tmp/dk2-fov.png" 20 || fail "dk2 foveated: nothing drawn in an eye"

# DK2 (PanoTools lens): the window's corners are outside the lens (black), its lens centres are not.
xvfb "$bin" live --device none --display dk2 --scene auditorium --frames 3 --render-scale 0.25 \
  --window-size 480x270 --capture "$tmp/dk2.png" --quiet >"$tmp/out" 2>"$tmp/err" || fail "dk2: $(cat "$tmp/err")"
grep -q "with the profile's lens and aberration" "$tmp/out" || fail "dk2: lens not used: $(cat "$tmp/out")"
[ "$(png_size "$tmp/dk2.png")" = "480 270" ] || fail "dk2: capture size"
rendered "$tmp/dk2.png" 20 || fail "dk2: nothing drawn in an eye"
out=$(probe "$tmp/dk2.png" 0.005,0.01 0.995,0.99 0.25,0.5 0.75,0.5)
if [ -n "$out" ]; then
  awk '$1 ~ /^0\.(005|995)/ && ($2 + $3 + $4) != 0 { bad = 1 }
       $1 ~ /^0\.(25|75),/ && ($2 + $3 + $4) == 0 { bad = 1 } END { exit bad }' <<<"$out" \
    || fail "dk2: the corners should be outside the lens (black) and the lens centres drawn: $out"
fi

# An empty analysis cache: the session runs Reddy's offline analysis in a headless EGL context
# while the window's context exists, then draws in the window again (render/egl_context.c's owner).
mkdir -p "$tmp/cache"
HMDLOD_CACHE_DIR="$tmp/cache" xvfb "$bin" live --device none --display dk2 --scene field --frames 5 \
  --render-scale 0.25 --window-size 320x180 --capture "$tmp/fresh.png" --quiet >"$tmp/out" 2>"$tmp/err" \
  || fail "fresh cache: $(cat "$tmp/err")"
grep -q "analysed" "$tmp/err" || fail "fresh cache: no analysis ran: $(cat "$tmp/err")"
[ "$(png_size "$tmp/fresh.png")" = "320 180" ] || fail "fresh cache: capture"
rendered "$tmp/fresh.png" 20 || fail "fresh cache: the window shows nothing after the headless analysis"

# A full disk during --record and --log (tests/enospc_shim.c, docs/live.md): the session stops with
# exit 1 and one message naming the file, which is kept cut back to its whole rows, as many as it says.
shim=${HMDLOD_ENOSPC_SHIM:-}
if [ -n "$shim" ] && [ -r "$shim" ]; then
  asan=$(ldd "$bin" 2>/dev/null | awk '/libasan/ {print $3; exit}')
  mkdir -p "$tmp/full"
  xvfb env LD_PRELOAD="${asan:+$asan }$shim" HMDLOD_ENOSPC_DIR="$tmp/full" HMDLOD_ENOSPC_AFTER=1500 \
    "$bin" live --device none --display dk2 --scene field --render-scale 0.25 --window-size 320x180 \
    --yaw-degps 30 --frames 300 --record "$tmp/full/head.csv" --log "$tmp/full/log.csv" --quiet \
    >"$tmp/full.out" 2>"$tmp/full.err"
  rc=$?
  msg=$(grep -o "[a-z]*\.csv: write failed: No space left on device; the session stopped, and the file holds its first [0-9]* rows (incomplete)" "$tmp/full.err")
  if [ $rc -ne 1 ] || [ -z "$msg" ]; then
    fail "disk full: exit $rc (want 1) or no message naming the file: $(cat "$tmp/full.err")"
  else
    name=${msg%%:*} kept=$(grep -o "first [0-9]*" <<<"$msg" | grep -o "[0-9]*")
    f="$tmp/full/$name"
    [ -f "$f" ] && [ -z "$(tail -c 1 "$f")" ] || fail "disk full: $name is missing or ends mid-row"
    [ "$(($(wc -l <"$f") - 1))" = "$kept" ] || fail "disk full: $name holds $(($(wc -l <"$f") - 1)) rows, the message says $kept"
    awk -F, -v n="$(head -1 "$f" | awk -F, '{print NF}')" 'NF != n { bad = 1 } END { exit bad }' "$f" ||
      fail "disk full: $name has a row with a different number of fields"
  fi
  [ -z "$(find "$tmp/full" -name '*.tmp.*')" ] || fail "disk full: temporaries left in $tmp/full"
else
  echo "skip: disk-full session (HMDLOD_ENOSPC_SHIM names no library; ctest sets it)"
fi

echo "live tests: $failures failed"
[ $failures -eq 0 ]
