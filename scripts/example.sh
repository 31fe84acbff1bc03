#!/usr/bin/env bash
# README command 1: install dependencies, build in Release, run the main job on the bundled
# example: validate and describe the example fabric and its tile, then run the whole
# pipeline (`yarnfit fit`: thin-shell fit to its stretch and pear-loop tests, uniform
# targets, yarn-level fit with a small swarm so that it finishes in a few minutes on 2
# cores) and compare the shell fit with the parameters the example was simulated from.
set -euo pipefail
# OpenMP threads spin while waiting by default; on a 2-core machine with other work running
# that slows the parallel energy loops 3-10x. Passive waiting gives the core back.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build-release -G Ninja -DCMAKE_BUILD_TYPE=Release -DYARNFIT_BUILD_TESTS=OFF -DYARNFIT_BUILD_BENCH=OFF
cmake --build build-release --parallel 2
yarnfit=./build-release/cli/yarnfit
example=examples/fabrics/stockinette_demo
out=build-release/example_output/stockinette_demo
$yarnfit db validate examples/fabrics
$yarnfit db list examples/fabrics
$yarnfit db show "$example"

echo
# A small swarm (16 particles x 6 iterations, 5 samples per direction) and a short local step
# keep the fits under a minute on 2 cores (36 s measured); the defaults (64 x 10, 7 and 20
# samples, 150 local evaluations) are for real calibrations.
fit_settings=(--particles 16 --iterations 6 --samples 5 --local-samples 12 --local-evaluations 40)
echo "== yarnfit fit $example --out $out ${fit_settings[*]}"
$yarnfit fit "$example" --out "$out" "${fit_settings[@]}" --force
$yarnfit db show "$example" --json > "$out/fabric.json"
python3 - "$out" <<'EOF'
import json, os, sys
out = sys.argv[1]
fit = json.load(open(os.path.join(out, "shell_fit.json")))
truth = json.load(open(os.path.join(out, "fabric.json")))["ground_truth"]
e = fit["errors"]
print(f"\nfitted errors (mean |error| / mean |measured|): stretch force {e['stretch_force_pct']:.2f} %, "
      f"compression {e['compression_pct']:.2f} %, pear-loop aspect ratio {e['bending_pct']:.2f} %")
print(f"{'parameter':<12} {'fitted':>12} {'ground truth':>13} {'difference':>11}")
for k in ["kxx", "kxy", "kyy", "kss", "kn1", "kn2", "ktheta_weft", "ktheta_bias", "ktheta_warp"]:
    v, t = fit["params"].get(k), truth.get(k)
    diff = f"{100 * (v / t - 1):+.1f} %" if v is not None and t else ""
    print(f"{k:<12} {v if v is not None else float('nan'):>12.4g} {t:>13.4g} {diff:>11}")
weak = fit.get("weakly_identified") or []
if weak:
    print("weakly identified (the tests pin them only loosely): " + ", ".join(weak))
print(f"fit time {fit['timing_s']:.1f} s")
print(f"results: {out}/shell_fit.json (parameters, errors, simulated vs measured curves)")
print(f"         {out}/uniform_targets.csv (uniform stress-strain targets for the yarn fit)")
print(f"         {out}/yarn_fit.json, yarn_curves.csv (yarn parameters, errors, simulated vs targets)")
print(f"         {out}/summary.txt (both stages, shown below)")
EOF
echo
cat "$out/summary.txt"
rm -f "$out/fabric.json"
