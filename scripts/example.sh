#!/usr/bin/env bash
# README command 1: install dependencies, build in Release, run the main job on the bundled
# example (today: validate and describe the example fabric and its tile).
set -euo pipefail
# OpenMP threads spin while waiting by default; on a 2-core machine with other work running
# that slows the parallel energy loops 3-10x. Passive waiting gives the core back.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build-release -G Ninja -DCMAKE_BUILD_TYPE=Release -DYARNFIT_BUILD_TESTS=OFF -DYARNFIT_BUILD_BENCH=OFF
cmake --build build-release --parallel 2
./build-release/cli/yarnfit db validate examples/fabrics
./build-release/cli/yarnfit db list examples/fabrics
./build-release/cli/yarnfit db show examples/fabrics/stockinette_demo
