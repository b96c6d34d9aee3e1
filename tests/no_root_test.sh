#!/usr/bin/env bash
# hmdlod never needs root at run time (issue 17 item 8): replay, devices, record (from a fake DK2 under
# umockdev, PLATFORM.md §6 CLI route) and lodgen, run as an unprivileged user with no supplementary
# groups, each working in a temporary folder that user owns. Run as root (CI containers often are),
# the commands drop to nobody (65534) with setpriv; run as anyone else, they run as that user, which
# already is the case under test. Skips (77) only when root lacks setpriv or umockdev-run.
set -u
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
here=$(cd "$(dirname "$0")" && pwd)
data="$here/data/umockdev"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
command -v umockdev-run >/dev/null || { echo "skip: umockdev-run is absent (apt-get install umockdev)"; exit 77; }

tmp=$(mktemp -d /tmp/hmdlod-noroot-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
if [ "$(id -u)" -eq 0 ]; then
  command -v setpriv >/dev/null || { echo "skip: running as root and setpriv is absent (util-linux)"; exit 77; }
  user=65534
  # --clear-groups drops root's groups too: nothing here may come from group membership.
  as_user() { setpriv --reuid=$user --regid=$user --clear-groups -- "$@"; }
  chown $user:$user "$tmp"
  chmod 0700 "$tmp"
  # The program, the fixtures and the shared data must be reachable by that user.
  as_user test -x "$bin" || { echo "skip: $bin is not executable by uid $user (a private checkout)"; exit 77; }
  as_user test -r "$data/dk2.ioctl" || { echo "skip: $data is not readable by uid $user"; exit 77; }
else
  user=$(id -u)
  as_user() { "$@"; }
fi
echo "running as uid $user"
# as_user_ok DESCRIPTION REGEX -- COMMAND...: exit 0 as the unprivileged user, stdout+stderr match REGEX
as_user_ok() {
  local what=$1 pattern=$2; shift 3
  local out; out=$(cd "$tmp" && as_user env HOME="$tmp" "$@" 2>&1); local rc=$?
  [ $rc -eq 0 ] || { fail "$what: exit $rc as uid $user: $out"; return; }
  grep -Eq -- "$pattern" <<<"$out" || fail "$what: output does not match /$pattern/: $out"
}
# owned FILE: exists and belongs to the unprivileged user (written by it, not by a helper as root)
owned() {
  [ -e "$1" ] || { fail "$1 was not written"; return; }
  [ "$(stat -c %u "$1")" = "$user" ] || fail "$1 belongs to uid $(stat -c %u "$1"), not $user"
}

# replay: a built-in scene rendered headless (EGL), its outputs in a folder of that user.
as_user_ok "replay" "frames within the budget" -- "$bin" replay --scene field --objects 4 --frames 10 \
  --render-scale 0.25 --out "$tmp/replay"
owned "$tmp/replay/frames.csv"

# devices: the fake DK2's hidraw node, opened as that user.
as_user_ok "devices" "can open: yes" -- \
  umockdev-run -d "$data/dk2-hidraw0.umockdev" -i /dev/hidraw0="$data/dk2.ioctl" -- "$bin" devices

# record: 100 DK2 stream reports (ID 0x0B, 64 bytes) 2 ms apart, as an umockdev script: each line
# "r DELAY_MS DATA", bytes below 32 written ^@ … ^_ (umockdev's script encoding).
report="^K$(printf '^@%.0s' $(seq 1 63))"
for _ in $(seq 1 100); do echo "r 2 $report"; done >"$tmp/dk2.script"
chmod 0644 "$tmp/dk2.script"
as_user_ok "record" "recorded [1-9][0-9]* reports" -- \
  umockdev-run -d "$data/dk2-hidraw0.umockdev" -i /dev/hidraw0="$data/dk2.ioctl" -s /dev/hidraw0="$tmp/dk2.script" \
  -- "$bin" record --device auto --out "$tmp/head.raw" --seconds 0.5
owned "$tmp/head.raw"

# lodgen: a 16×16-quad grid (512 triangles) into a .lod.
awk 'BEGIN { n = 17
  for (j = 0; j < n; ++j) for (i = 0; i < n; ++i) printf "v %d %d %g\n", i, j, 0.1 * sin(i + j)
  for (j = 0; j < n - 1; ++j) for (i = 0; i < n - 1; ++i) { a = j * n + i + 1
    printf "f %d %d %d\nf %d %d %d\n", a, a + 1, a + n + 1, a, a + n + 1, a + n } }' >"$tmp/grid.obj"
chmod 0644 "$tmp/grid.obj"
as_user_ok "lodgen" "" -- "$bin" lodgen "$tmp/grid.obj" --levels 3 --out "$tmp/grid.lod"
owned "$tmp/grid.lod"

echo "no-root tests: $failures failed"
[ $failures -eq 0 ]
