#!/usr/bin/env bash
# Fuzzing (docs/fuzzing.md): builds build-fuzz (clang, libFuzzer + ASan + UBSan) with scripts/build.sh,
# then runs every fuzz target in tests/fuzz for HMDLOD_FUZZ_SECONDS (default 30) each, two at a time,
# each on a temporary copy of its seed corpus (the repository is never written). One line per
# target: executions, corpus size, result. Crash, leak, timeout and out-of-memory inputs are kept
# in the folder named at the end (HMDLOD_FUZZ_ARTIFACTS, default build-fuzz/fuzz-findings); exit 1
# on any finding. `scripts/fuzz.sh NAME...` runs only those targets.
# Options: HMDLOD_FUZZ_SECONDS, HMDLOD_FUZZ_JOBS (default 2), HMDLOD_FUZZ_NO_BUILD=1 (reuse the build),
# HMDLOD_FUZZ_BUILD_DIR (default build-fuzz: a folder configured with HMDLOD_FUZZ), HMDLOD_FUZZ_SEED (libFuzzer's -seed; by default
# one from the commit, so rerunning a commit makes the same inputs and each new commit new ones; 0 is
# a random seed each run).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${HMDLOD_FUZZ_SECONDS:-30}
jobs=${HMDLOD_FUZZ_JOBS:-2}
build_dir=${HMDLOD_FUZZ_BUILD_DIR:-build-fuzz}
findings=${HMDLOD_FUZZ_ARTIFACTS:-$build_dir/fuzz-findings}
default_seed=0
commit=$(git rev-parse HEAD 2>/dev/null || true)
[ -n "$commit" ] && default_seed=$(( 16#${commit:0:7} + 1 ))
seed=${HMDLOD_FUZZ_SEED:-$default_seed}

# Every target has a seed corpus folder; that list is the list of targets.
all=()
for d in tests/fuzz/corpus/*/; do all+=("$(basename "$d")"); done
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
for t in "${targets[@]}"; do
  if [ ! -d "tests/fuzz/corpus/$t" ]; then
    echo "fuzz.sh: unknown target '$t' (targets: ${all[*]})" >&2
    exit 1
  fi
done

# Largest input per target: a few reports or records more than the seeds, a page or two of text.
max_len() {
  case $1 in
    report_*) echo 2048 ;;
    stream|recording|recording_repair|lodfile|lodfile_repair) echo 8192 ;;
    trace|scenefile|mesh_import|bench_result) echo 16384 ;;
    *) echo 4096 ;;
  esac
}

if [ "${HMDLOD_FUZZ_NO_BUILD:-0}" != 1 ]; then
  BUILD_DIR=$build_dir BUILD_TARGET=fuzz_all \
    CMAKE_ARGS="-DHMDLOD_FUZZ=ON -DHMDLOD_WERROR=ON -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++" \
    scripts/build.sh
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/hmdlod-fuzz-run.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$findings"

# One target: its corpus copied, libFuzzer for $seconds, a result line in $work/NAME.line.
run_one() {
  local t=$1 dir=$work/$1
  mkdir -p "$dir/corpus" "$dir/artifacts"
  cp tests/fuzz/corpus/"$t"/* "$dir/corpus/"
  [ -d "tests/fuzz/regress/$t" ] && cp tests/fuzz/regress/"$t"/* "$dir/corpus/" 2>/dev/null || true
  local seeds; seeds=$(find "$dir/corpus" -type f | wc -l)
  local dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
  local rc=0 start; start=$(date +%s)
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
    LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp:print_suppressions=0" \
    UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$build_dir/tests/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -seed="$seed" \
    -max_len="$(max_len "$t")" -artifact_prefix="$dir/artifacts/" -print_final_stats=1 "${dict[@]}" \
    "$dir/corpus" >"$dir/log" 2>&1 || rc=$?
  local execs; execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)
  local size; size=$(find "$dir/corpus" -type f | wc -l)
  local result=ok
  # slow-unit-* files (an input over 10 s that still finished; on a loaded machine, any) are kept
  # as a note; crash-, leak-, timeout- and oom- files and a non-zero exit are findings.
  local slow; slow=$(find "$dir/artifacts" -name 'slow-unit-*' | wc -l)
  if [ "$slow" -gt 0 ]; then
    mkdir -p "$findings/$t"
    cp "$dir"/artifacts/slow-unit-* "$findings/$t/"
    rm -f "$dir"/artifacts/slow-unit-*
    result="ok ($slow slow unit(s) kept)"
  fi
  if [ "$rc" -ne 0 ] || [ -n "$(ls -A "$dir/artifacts")" ]; then
    mkdir -p "$findings/$t"
    cp "$dir/log" "$findings/$t/log"
    cp "$dir"/artifacts/* "$findings/$t/" 2>/dev/null || true
    result="FINDING (exit $rc): $(cd "$dir/artifacts" && ls | tr '\n' ' ')"
  fi
  printf 'fuzz %-18s %10s execs in %3d s, corpus %4d -> %4d, %s\n' "$t" "${execs:-?}" \
    "$(( $(date +%s) - start ))" "$seeds" "$size" "$result" >"$work/$t.line"
}

start=$(date +%s)
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  run_one "$t" &
  running=$((running + 1))
done
wait || true

status=0
for t in "${targets[@]}"; do
  if [ -f "$work/$t.line" ]; then
    cat "$work/$t.line"
    grep -q FINDING "$work/$t.line" && status=1
  else
    echo "fuzz $t: did not report (the runner failed)"
    status=1
  fi
done
echo "fuzz: ${#targets[@]} targets x ${seconds} s, $jobs at a time, seed $seed, in $(( $(date +%s) - start )) s"
if [ "$status" -ne 0 ]; then
  echo "fuzz: FINDINGS kept in $findings (reproduce: $build_dir/tests/fuzz/fuzz_NAME FILE; docs/fuzzing.md)"
fi
exit "$status"
