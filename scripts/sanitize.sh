#!/usr/bin/env bash
# The test suite under sanitizers (issue 52, docs/reliability.md):
#   scripts/sanitize.sh [address|thread|all] [ctest arguments...]
# address (default): the whole tree built with AddressSanitizer and UndefinedBehaviorSanitizer
#   in build-asan/, every test run; any report fails the test it happened in.
# thread: the tree built with ThreadSanitizer in build-tsan/, the service and batch tests run
#   (the code that runs threads of its own: the job queue, the HTTP server, the batch runner).
# all: both. Logs: build-asan/sanitize.log, build-tsan/sanitize.log.
# address --resume: the whole suite takes about four hours under ASan on two cores, so a run can
#   be stopped and carried on: the tests that passed in build-asan/sanitize.log are skipped and the
#   rest run, appended to the same log, provided the tree is still at the commit the log began at.
set -euo pipefail
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
cd "$(dirname "$0")/.."
mode=${1:-address}
[ $# -gt 0 ] && shift
bash scripts/install_deps.sh

# The commit the tree is at, marked when it differs from that commit.
tree_commit() {
  local commit
  commit=$(git rev-parse HEAD 2>/dev/null || echo "not a git checkout")
  if [ -n "$(git status --porcelain --untracked-files=no 2>/dev/null)" ]; then commit="$commit with changes"; fi
  echo "$commit"
}

# The numbers of the tests the log says passed, one a line.
passed_tests() {
  { grep -E "Test +#[0-9]+: .* Passed" "$1" || true; } | sed -E 's/.*Test +#([0-9]+): .*/\1/' | sort -nu
}

run_address() {
  local build=build-asan resume=0
  if [ "${1:-}" = --resume ]; then resume=1; shift; fi
  # -O2, not -O1: Eigen's small fixed-size products are what the whole-fit tests spend their
  # time in, and at -O1 they run ten times slower than at -O2. Frame pointers keep stacks
  # readable; UB is fatal so that ctest sees it. The libraries compile in unity batches (as the
  # fuzz build does), which halves this build on two cores.
  cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DYARNFIT_BUILD_BENCH=OFF -DYARNFIT_TEST_TIMEOUT_SCALE=5 \
    -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 \
    -DCMAKE_CXX_FLAGS="-O2 -g1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined"
  cmake --build $build --parallel "$(nproc)"
  local log=$build/sanitize.log commit total run=()
  commit=$(tree_commit)
  total=$(ctest --test-dir $build -N | sed -nE 's/^Total Tests: ([0-9]+)/\1/p')
  if [ $resume = 1 ]; then
    if [ ! -f $log ] || [ "$(cat $build/sanitize.commit 2>/dev/null)" != "$commit" ] || [[ $commit == *changes ]]; then
      echo "sanitize.sh: cannot resume: $log is not of this tree ($commit); run without --resume" >&2
      return 2
    fi
    # The tests not yet passed, by number (ctest -I's file: no range, then the numbers).
    local left
    left=$(comm -23 <(seq 1 "$total" | sort) <(passed_tests $log | sort) | sort -n | paste -sd,)
    echo "0,0,0,${left:-0}" > $build/sanitize.left
    run=(-I $build/sanitize.left)
  else
    echo "$commit" > $build/sanitize.commit
    : > $log
  fi
  echo "== sanitize.sh address: a part started $(date -u '+%F %T') UTC at commit $commit" | tee -a $log
  # Leaks are checked too (LeakSanitizer, on with ASan); suppressions carry their reasons.
  # Open MPI's components stay loaded to the end, so that a leak report of an MPI rank names
  # the library it came from (scripts/sanitizer/lsan.supp).
  local status=0
  OMPI_MCA_mca_base_component_disable_dlclose=1 \
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1" \
  LSAN_OPTIONS="suppressions=$PWD/scripts/sanitizer/lsan.supp:print_suppressions=0" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    ctest --test-dir $build --output-on-failure --parallel 2 --timeout 4500 "${run[@]}" "$@" 2>&1 | tee -a $log ||
    status=$?
  # The whole log's count, over every part.
  echo "== sanitize.sh address: $(passed_tests $log | wc -l) of $total tests passed at commit $commit," \
    "in $(grep -c '^== sanitize.sh address: a part started' $log) part(s)" | tee -a $log
  return $status
}

run_thread() {
  local build=build-tsan
  # clang, so that OpenMP is LLVM's libomp: with TSan it loads Archer (libomp-dev), which tells
  # TSan about OpenMP's barriers. GCC's libgomp does not, so every parallel loop whose results
  # the main thread reads after the loop's barrier would be reported as a race.
  if [ -f $build/CMakeCache.txt ] && ! grep -q "CMAKE_CXX_COMPILER:.*clang" $build/CMakeCache.txt; then rm -rf $build; fi
  CC=clang CXX=clang++ cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=Sanitize -DYARNFIT_BUILD_BENCH=OFF \
    -DCMAKE_CXX_FLAGS="-O1 -g1 -fno-omit-frame-pointer -fsanitize=thread" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread"
  cmake --build $build --parallel "$(nproc)" --target test_service test_batch yarnfit
  # The service and batch suites, the code with threads of its own (HTTP server, job queue,
  # batch runner) and the OpenMP loops of the fits they run, in the test and in every `yarnfit`
  # it starts. Not instrumented (OpenMPI, libomp itself) is not checked. Suppressions, each
  # with its reason: scripts/sanitizer/tsan.supp.
  : > $build/sanitize.log
  local status=0
  for t in tests/service/test_service tests/batch/test_batch; do
    TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:ignore_noninstrumented_modules=1:suppressions=$PWD/scripts/sanitizer/tsan.supp" \
      "$build/$t" "$@" 2>&1 | tee -a $build/sanitize.log || status=1
  done
  return $status
}

case "$mode" in
  address) run_address "$@" ;;
  thread) run_thread "$@" ;;
  all) run_address "$@"; run_thread "$@" ;;
  *) echo "usage: scripts/sanitize.sh [address|thread|all] [ctest arguments...]" >&2; exit 2 ;;
esac
