#!/usr/bin/env bash
# Set-up for a fresh machine: install the packages (scripts/setup.sh), configure and build into
# build/ (Release with debug info). Safe to run again; it only redoes what changed.
# Options: BUILD_DIR (default build), CMAKE_ARGS (extra configure arguments), BUILD_TARGET (one
# target instead of all).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
build_dir=${BUILD_DIR:-build}
# shellcheck disable=SC2086
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo ${CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$(nproc)" ${BUILD_TARGET:+--target "$BUILD_TARGET"}
