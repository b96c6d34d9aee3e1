#!/usr/bin/env bash
# hmdlod live as a user meets it, under Xvfb (PLATFORM.md §3): the issue's acceptance command (120
# frames, the summary's present intervals, a PNG of the window), a session stopped by SIGINT (the
# summary printed, the head trace complete and replayable), --list-monitors, and a distorted DK2
# capture whose lens border is black and whose centre is not. Skips (77) only when xvfb-run is absent.
set -u
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
command -v xvfb-run >/dev/null || { echo "skip: xvfb-run is absent (apt-get install xvfb xauth)"; exit 77; }
tmp=$(mktemp -d /tmp/hmdlod-live-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# png_size FILE: "W H" from the IHDR chunk, or nothing when FILE is not a PNG.
png_size() {
  [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || return 1
  od -An -tu1 -j16 -N8 "$1" | awk '{ print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8 }'
}

# The acceptance command.
xvfb-run -a "$bin" live --device none --display vive --scene auditorium --frames 120 --capture "$tmp/live.png" \
  >"$tmp/out" 2>"$tmp/err"
rc=$?
[ $rc -eq 0 ] || fail "acceptance: exit $rc: $(tail -3 "$tmp/err")"
grep -Eq "present interval ms: median [0-9.]+ +p99 [0-9.]+ +stddev [0-9.]+" "$tmp/out" \
  || fail "acceptance: no present intervals in the summary: $(cat "$tmp/out")"
grep -Eq "frames 120, missed [0-9]+" "$tmp/out" || fail "acceptance: not 120 frames: $(cat "$tmp/out")"
size=$(png_size "$tmp/live.png") || fail "acceptance: $tmp/live.png is not a PNG"
window=$(grep -o "window [0-9]* x [0-9]*" "$tmp/out" | awk '{ print $2, $4 }')
[ "$size" = "$window" ] || fail "acceptance: PNG is '$size', the window '$window'"
stray=$(ls "$tmp" | grep -v -E '^(out|err|live\.png)$')
[ -z "$stray" ] || fail "acceptance: files left beside the capture: $stray"

# Esc/close/SIGINT: a session without --frames stopped by SIGINT prints its summary and leaves a
# complete head trace (no .partial) that replay reads back.
xvfb-run -a bash -c '"$0" live --device none --display dk2 --scene field --render-scale 0.25 --window-size 320x180 \
    --yaw-degps 30 --record "$1/head.csv" --quiet >"$1/int.out" 2>"$1/int.err" & pid=$!; sleep 4; kill -INT $pid; wait $pid' \
  "$bin" "$tmp"
rc=$?
[ $rc -eq 0 ] || fail "SIGINT: exit $rc: $(tail -3 "$tmp/int.err")"
grep -q "interrupted" "$tmp/int.err" || fail "SIGINT: no 'interrupted' note: $(cat "$tmp/int.err")"
grep -q "present interval ms" "$tmp/int.out" || fail "SIGINT: no summary: $(cat "$tmp/int.out")"
[ -e "$tmp/head.csv" ] && [ ! -e "$tmp/head.csv.partial" ] || fail "SIGINT: the head trace is missing or partial"
rows=$(($(wc -l <"$tmp/head.csv") - 1))
frames=$(grep -o "frames [0-9]*" "$tmp/int.out" | awk '{ print $2 }')
[ "$rows" -ge 2 ] && [ "$rows" = "$frames" ] || fail "SIGINT: $rows trace rows for $frames frames"
# The scripted yaw turns about +Y at 30 deg/s: the last row's quaternion has |qy| > 0.
awk -F, 'END { exit !($4 > 0.01 || $4 < -0.01) }' "$tmp/head.csv" || fail "SIGINT: the head did not turn"
"$bin" replay --trace "$tmp/head.csv" --scene field --render-scale 0.25 --selector none --quiet --out "$tmp/re" \
  2>"$tmp/re.err" || fail "the recorded head trace does not replay: $(cat "$tmp/re.err")"

# Monitors: Xvfb's one screen, and the note on non-desktop headsets.
out=$(xvfb-run -a "$bin" live --list-monitors 2>&1) || fail "--list-monitors: $out"
grep -q "non-desktop" <<<"$out" || fail "--list-monitors: no non-desktop note: $out"
grep -Eq "^0 +[^ ]+ +[0-9]+x[0-9]+" <<<"$out" || fail "--list-monitors: no monitor 0: $out"
xvfb-run -a "$bin" live --device none --monitor 5 --frames 2 >/dev/null 2>"$tmp/err"
[ $? -eq 1 ] && grep -q "there are 1 monitors" "$tmp/err" || fail "--monitor 5: $(cat "$tmp/err")"

# DK2 (PanoTools lens): the window's corners are outside the lens (black), its lens centres are not.
xvfb-run -a "$bin" live --device none --display dk2 --scene auditorium --frames 3 --render-scale 0.25 \
  --window-size 480x270 --capture "$tmp/dk2.png" --quiet >"$tmp/out" 2>"$tmp/err" || fail "dk2: $(cat "$tmp/err")"
grep -q "with the profile's lens and aberration" "$tmp/out" || fail "dk2: lens not used: $(cat "$tmp/out")"
[ "$(png_size "$tmp/dk2.png")" = "480 270" ] || fail "dk2: capture size"

echo "live tests: $failures failed"
[ $failures -eq 0 ]
