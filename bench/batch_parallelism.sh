#!/usr/bin/env bash
# The jobs × threads study of issue 18: the same batch run as 1 job × 2 threads and as
# 2 jobs × 1 thread on this 2-core machine, shell stage only (the four acrylic records of
# ../shared, real data, in-plane fits) and the whole pipeline (four copies of the bundled
# example: in-plane and pear-loop fits, then the yarn fit with README command 1's settings),
# each pair run alternately ROUNDS times. Prints the wall time of every run
# and the median ratio. A benchmark, not a test: it takes about 10 minutes per round.
#
#   bash bench/batch_parallelism.sh [BUILD_DIR (build-release)] [ROUNDS (2)]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-release}
rounds=${2:-2}
yarnfit="$PWD/$build/cli/yarnfit"
shared="$PWD/../shared"
work=$(mktemp -d /tmp/yarnfit-batch-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
export OMP_WAIT_POLICY=passive

# Databases.
python3 scripts/build_acrylic_records.py "$work/acrylic" >/dev/null
# Four copies of the bundled example (pear-loop tests included), under their own ids.
mkdir -p "$work/demo"
for i in 1 2 3 4; do
  cp -r examples/fabrics/stockinette_demo "$work/demo/demo_$i"
  sed -i "s/^id: stockinette_demo/id: demo_$i/" "$work/demo/demo_$i/fabric.yaml"
done

# The settings of README command 1 (scripts/example.sh).
yarn_opts="--particles 16 --iterations 6 --samples 5 --local-samples 12 --local-evaluations 40"
run() {  # run NAME DB STAGES JOBS THREADS
  local out="$work/out_$1_$4x$5_$RANDOM"
  local start end
  start=$(date +%s.%N)
  "$yarnfit" batch "$2" --out "$out" --stages "$3" --jobs "$4" --threads-per-job "$5" $yarn_opts --quiet || true
  end=$(date +%s.%N)
  python3 -c "print(f'{$end - $start:.1f}')"
  rm -rf "$out"
}

printf '%-22s %-8s %10s %10s %8s\n' "batch" "round" "1x2 [s]" "2x1 [s]" "2x1/1x2"
for name in acrylic demo; do
  if [ "$name" = acrylic ]; then db="$work/acrylic"; stages=shell; else db="$work/demo"; stages=all; fi
  ratios=()
  for r in $(seq 1 "$rounds"); do
    if [ $((r % 2)) -eq 1 ]; then a=$(run "$name" "$db" "$stages" 1 2); b=$(run "$name" "$db" "$stages" 2 1)
    else b=$(run "$name" "$db" "$stages" 2 1); a=$(run "$name" "$db" "$stages" 1 2); fi
    ratio=$(python3 -c "print(f'{$b / $a:.3f}')")
    ratios+=("$ratio")
    printf '%-22s %-8s %10s %10s %8s\n' "$name ($stages)" "$r" "$a" "$b" "$ratio"
  done
  python3 -c "import statistics,sys; print(f'  median 2x1/1x2 for $name: {statistics.median(map(float, sys.argv[1:])):.3f}')" "${ratios[@]}"
done
