#!/bin/sh
# Installs the embeddable core into a temporary prefix (cmake --install), builds examples/embed.c
# against that copy alone through pkg-config, as README tells an engine developer, runs it and checks
# its output: every frame within budget, levels and LP share printed.
# Usage: embed_install.sh BUILD_DIR SOURCE_DIR C_COMPILER [EXTRA_CFLAGS]
set -eu
build=$1 src=$2 cc=$3 extra=${4:-}
prefix=$(mktemp -d "${TMPDIR:-/tmp}/hmdlod-install.XXXXXX")
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
for f in include/hmdlod/base/base.h include/hmdlod/acuity/acuity.h include/hmdlod/lod/lod.h \
         lib/libhmdlod_lod.a lib/libhmdlod_acuity.a lib/libhmdlod_base.a lib/pkgconfig/hmdlod.pc; do
    [ -f "$prefix/$f" ] || { echo "embed_install: $prefix/$f: not installed"; exit 1; }
done
# Only the installed copy: the source tree is not on the include path.
flags=$(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs hmdlod)
# shellcheck disable=SC2086
"$cc" -std=c11 -Wall -Wextra -Werror $extra "$src/examples/embed.c" $flags -o "$prefix/embed"
# HMDLOD_TEST_WRAPPER: a command to run the program under (scripts/valgrind-tests.sh sets valgrind).
# shellcheck disable=SC2086
out=$(${HMDLOD_TEST_WRAPPER:-} "$prefix/embed")
echo "$out"
frames=$(echo "$out" | grep -c "predicted cost .* ms of budget .* ms: within" || true)
[ "$frames" -eq 2 ] || { echo "embed_install: expected 2 frames within budget, got $frames"; exit 1; }
echo "$out" | grep -q "chosen levels" || { echo "embed_install: no level histogram"; exit 1; }
echo "$out" | grep -q "% of the LP bound" || { echo "embed_install: no LP share"; exit 1; }
echo "embed_install: ok"
