#!/usr/bin/env bash
# EGL/GL and window failures made real (docs/HARD_CASES.md "Faults"): each rendering command, with
# EGL failing at each of its three steps, exits 1 with one message from hmdlod naming the step and
# the cause, and leaves no output behind (analyze leaves its .lod as it was); `live` with no X
# server to talk to does the same. What fails here for real: glvnd with no vendor file (no driver
# at all), a software driver that does not exist (the display cannot be initialised), an OpenGL
# version below the 4.5 core we ask for (no context). MESA_LOADER_DRIVER_OVERRIDE=nonexistent and
# EGL_PLATFORM=bogus do not fail on Mesa 22 (it falls back to swrast; we pick our platform), so
# they are not used.
set -u
bin=${HMDLOD_BIN:?HMDLOD_BIN must point at the hmdlod program}
shared=${HMDLOD_SHARED:-../shared}
tmp=$(mktemp -d /tmp/hmdlod-glfault-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_fail WHAT REGEX OUTPUT -- COMMAND...: exit 1, exactly one stderr line from hmdlod, matching
# REGEX, and OUTPUT (a file or folder) absent afterwards.
expect_fail() {
  local what=$1 pattern=$2 output=$3; shift 4
  "$@" >"$tmp/out" 2>"$tmp/err"; local rc=$?
  local ours; ours=$(grep -c '^hmdlod: ' "$tmp/err")
  [ $rc -eq 1 ] || { fail "$what: exit $rc (want 1): $(cat "$tmp/err")"; return; }
  [ "$ours" -eq 1 ] || fail "$what: $ours messages from hmdlod (want 1): $(cat "$tmp/err")"
  grep -Eq -- "$pattern" "$tmp/err" || fail "$what: stderr does not match /$pattern/: $(cat "$tmp/err")"
  [ ! -e "$output" ] || fail "$what: left $output behind"
  echo "ok: $what: $(grep '^hmdlod: ' "$tmp/err")"
}

# A .lod for analyze (lodgen needs no GL): the shared Suzanne, else a generated 16×16 grid.
mesh="$shared/data/meshes/suzanne.obj"
if [ ! -f "$mesh" ]; then
  mesh="$tmp/grid.obj"
  awk 'BEGIN { n = 16; for (j = 0; j <= n; ++j) for (i = 0; i <= n; ++i) printf "v %g %g %g\n", i / n, j / n, 0.1 * sin(i) * cos(j);
               for (j = 0; j < n; ++j) for (i = 0; i < n; ++i) { a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 1; d = c + 1;
               printf "f %d %d %d\nf %d %d %d\n", a, b, d, a, d, c } }' >"$mesh"
fi
"$bin" lodgen "$mesh" --simplifier meshopt --levels 3 --samples 5000 --out "$tmp/m.lod" >/dev/null 2>"$tmp/err" ||
  fail "lodgen (no GL) failed: $(cat "$tmp/err")"
sum0=$(cksum <"$tmp/m.lod")

i=0
while IFS='|' read -r env_vars pattern; do
  i=$((i + 1))
  expect_fail "replay, $env_vars" "$pattern" "$tmp/replay$i" -- env $env_vars "$bin" replay --scene field \
    --objects 50 --frames 5 --render-scale 0.25 --out "$tmp/replay$i"
  expect_fail "demo, $env_vars" "$pattern" "$tmp/demo$i" -- env $env_vars "$bin" demo --frames 5 \
    --render-scale 0.25 --out "$tmp/demo$i"
  expect_fail "analyze, $env_vars" "$pattern" "$tmp/m.lod.partial" -- env $env_vars "$bin" analyze "$tmp/m.lod" \
    --views 6 --size 64
  [ "$(cksum <"$tmp/m.lod")" = "$sum0" ] || fail "analyze, $env_vars: the .lod changed"
  ls "$tmp" | grep -Eq '\.(tmp|partial)' && fail "$env_vars: a temporary file was left: $(ls "$tmp")"
done <<'CASES'
__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json|renderer: no EGL driver loaded .*__EGL_VENDOR_LIBRARY_FILENAMES
LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=nonexistent|renderer: EGL cannot initialise a headless display .*EGL_NOT_INITIALIZED
MESA_GL_VERSION_OVERRIDE=3.3|renderer: cannot create an OpenGL 4.5 core context \(EGL_BAD_MATCH
CASES

# live: no X server at that address, or an address that is not one.
for display in :4711 bogus; do
  expect_fail "live, DISPLAY=$display" "window: GLFW cannot start: X11: Failed to open display $display" \
    "$tmp/live.csv" -- env DISPLAY=$display WAYLAND_DISPLAY= timeout 30 "$bin" live --device none --frames 2 \
    --record "$tmp/live.csv"
done

echo "gl fault tests: $failures failed"
[ $failures -eq 0 ]
