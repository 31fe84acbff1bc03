#!/usr/bin/env bash
# Coverage-guided fuzzing of every reader of bytes a user or a client controls (issue 52,
# docs/reliability.md), with libFuzzer, AddressSanitizer and UndefinedBehaviorSanitizer.
#
#   scripts/fuzz.sh --list             builds the targets if needed; names them, one a line
#   scripts/fuzz.sh TARGET SECONDS     fuzzes TARGET for SECONDS (more libFuzzer flags may follow)
#   scripts/fuzz.sh --all SECONDS      every target for SECONDS each, one per core at a time
#                                      (.ci/run's smoke run)
#
# Installs what it needs (scripts/install_deps.sh), builds in build-fuzz/ with clang. Each
# target starts from the seeds the project writes itself (fuzz/write_seeds.cpp, into
# build-fuzz/seeds/TARGET) and keeps what it finds in build-fuzz/corpus/TARGET, so the next run
# goes on from there. A crash stops the run with exit 1 and leaves its input in
# build-fuzz/artifacts/TARGET/; keep it as a regression test (tests/fuzz_regressions/).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-fuzz

usage() {
  echo "usage: scripts/fuzz.sh --list | TARGET SECONDS [libFuzzer flags...] | --all SECONDS" >&2
  exit 2
}
[ $# -ge 1 ] || usage

build_targets() {
  bash scripts/install_deps.sh >&2
  if [ ! -f "$build/CMakeCache.txt" ]; then
    # Every library instrumented for coverage and checked by ASan and UBSan (a UB report stops
    # the run like a crash); -O1 keeps the reports' stacks readable and the runs fast. The
    # libraries compile in unity batches of 8 files: every CI run makes this build, and no
    # fuzz target depends on the last bit of a result.
    CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Fuzz \
      -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 \
      -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined" \
      -DYARNFIT_BUILD_FUZZ=ON -DYARNFIT_BUILD_TESTS=OFF -DYARNFIT_BUILD_BENCH=OFF >&2
  fi
  cmake --build "$build" --target fuzz_targets --parallel "$(nproc)" >&2
}

targets() { cat "$build/fuzz_targets.txt"; }

run_target() {
  local target=$1 seconds=$2
  shift 2
  grep -qx "$target" "$build/fuzz_targets.txt" || { echo "fuzz.sh: no target '$target' (see --list)" >&2; exit 2; }
  local seeds="$build/seeds/$target" corpus="$build/corpus/$target" artifacts="$build/artifacts/$target/"
  mkdir -p "$corpus" "$artifacts"
  [ -d "$seeds" ] || { echo "fuzz.sh: no seeds for $target" >&2; exit 1; }
  echo "== $target: $seconds s from $(ls "$seeds" | wc -l) seeds and $(ls "$corpus" | wc -l) corpus inputs" >&2
  # Stopped at the time given; an input that runs 30 s or takes 2 GB is a finding too.
  "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 \
    -artifact_prefix="$artifacts" -print_final_stats=1 "$@" "$corpus" "$seeds"
}

case "$1" in
  --list)
    [ $# -eq 1 ] || usage
    build_targets
    targets
    ;;
  --all)
    [ $# -eq 2 ] || usage
    build_targets
    rm -rf "$build/seeds" && "$build/fuzz/fuzz_write_seeds" . "$build/seeds" >&2
    # As many targets at once as there are cores (each libFuzzer run is one process), each
    # into its own log, shown whole when it ends; any failure fails the run.
    mkdir -p "$build/logs"
    failed=0
    run_logged() { run_target "$1" "$2" >"$build/logs/$1.log" 2>&1; }
    show() { cat "$build/logs/$1.log"; }
    pending=($(targets))
    while [ ${#pending[@]} -gt 0 ]; do
      batch=("${pending[@]:0:$(nproc)}")
      pending=("${pending[@]:$(nproc)}")
      pids=()
      for t in "${batch[@]}"; do run_logged "$t" "$2" & pids+=($!); done
      for i in "${!batch[@]}"; do
        if ! wait "${pids[$i]}"; then failed=1; echo "== ${batch[$i]}: FAILED" >&2; fi
        show "${batch[$i]}" >&2
      done
    done
    exit $failed
    ;;
  -*) usage ;;
  *)
    [ $# -ge 2 ] || usage
    build_targets
    rm -rf "$build/seeds" && "$build/fuzz/fuzz_write_seeds" . "$build/seeds" >&2
    run_target "$@"
    ;;
esac
