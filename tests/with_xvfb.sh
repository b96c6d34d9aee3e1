#!/usr/bin/env bash
# with_xvfb.sh COMMAND [ARGS...]: runs COMMAND under a private Xvfb that is known to accept
# connections before COMMAND starts, and that stays up between them. Exits with COMMAND's status;
# 77 (skip) when Xvfb is absent.
#  - Ready: Xvfb picks a free display itself and writes its number (-displayfd) only once it listens —
#    what xvfb-run -a cannot promise when servers start close together. The number comes through a
#    FIFO, so the wait is a blocking read that ends when Xvfb writes it or exits, bounded by
#    60 s × HMDLOD_TEST_TIME_SCALE; then one X connection (xdpyinfo, when x11-utils is installed)
#    must succeed, polled to the same bound.
#  - No reset (-noreset): by default an X server resets when its last client disconnects, and a
#    client that connects during the reset is dropped. hmdlod live opens the display twice (the
#    monitor list, then the window), and on a loaded machine its second XOpenDisplay met the reset
#    of its first: "X11: Failed to open display :0" in about half of the runs when three sessions
#    ran beside two busy loops, none with -noreset.
set -u
command -v Xvfb >/dev/null || { echo "skip: Xvfb is absent (apt-get install xvfb)"; exit 77; }
wait_s=$(awk -v s="${HMDLOD_TEST_TIME_SCALE:-1}" 'BEGIN { s += 0; if (s < 1) s = 1; if (s > 1000) s = 1000; printf "%d", 60 * s }')
dir=$(mktemp -d /tmp/hmdlod-xvfb-XXXXXX)
pid=
cleanup() {
  [ -n "$pid" ] && kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# reachable DISPLAY: an X connection to it succeeds before the deadline (and while Xvfb runs).
reachable() {
  command -v xdpyinfo >/dev/null || return 0 # -displayfd alone: the server listens once it wrote its number
  local deadline=$((SECONDS + wait_s))
  until DISPLAY=$1 XAUTHORITY= xdpyinfo >/dev/null 2>"$dir/xdpyinfo.err"; do
    kill -0 "$pid" 2>/dev/null && [ $SECONDS -lt $deadline ] || return 1
    sleep 0.1
  done
}

mkfifo "$dir/displayfd"
for try in 1 2 3; do
  Xvfb -displayfd 3 -noreset -screen 0 1280x1024x24 -nolisten tcp 3>"$dir/displayfd" 2>"$dir/xvfb.log" &
  pid=$!
  num=
  read -r -t "$wait_s" num <"$dir/displayfd"
  if [[ $num =~ ^[0-9]+$ ]] && kill -0 "$pid" 2>/dev/null && reachable ":$num"; then
    DISPLAY=":$num" XAUTHORITY= "$@"
    exit $?
  fi
  kill "$pid" 2>/dev/null; wait "$pid" 2>/dev/null; pid=
done
echo "with_xvfb.sh: no Xvfb accepted connections after 3 tries (${wait_s} s each): $(tail -n 3 "$dir/xvfb.log")" \
  "$(cat "$dir/xdpyinfo.err" 2>/dev/null)" >&2
exit 1
