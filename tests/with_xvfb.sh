#!/usr/bin/env bash
# with_xvfb.sh COMMAND [ARGS...]: runs COMMAND under a private Xvfb that is known to accept
# connections before COMMAND starts. Xvfb picks a free display itself and writes its number
# (-displayfd) only once it listens — what xvfb-run -a cannot promise when servers start close
# together: its display search and readiness wait let a client meet no server now and then
# ("Failed to open display"). Exits with COMMAND's status; 77 (skip) when Xvfb is absent.
set -u
command -v Xvfb >/dev/null || { echo "skip: Xvfb is absent (apt-get install xvfb)"; exit 77; }
dir=$(mktemp -d /tmp/hmdlod-xvfb-XXXXXX)
pid=
cleanup() {
  [ -n "$pid" ] && kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
for try in 1 2 3; do
  : >"$dir/display"
  Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$dir/display" 2>"$dir/xvfb.log" &
  pid=$!
  for _ in $(seq 1 400); do # up to 20 s: the number appears when the server listens
    [ -s "$dir/display" ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.05
  done
  num=$(tr -dc '0-9' <"$dir/display")
  if [ -n "$num" ] && kill -0 "$pid" 2>/dev/null; then
    DISPLAY=":$num" XAUTHORITY= "$@"
    exit $?
  fi
  kill "$pid" 2>/dev/null; wait "$pid" 2>/dev/null; pid=
done
echo "with_xvfb.sh: Xvfb did not start after 3 tries: $(tail -n 3 "$dir/xvfb.log")" >&2
exit 1
