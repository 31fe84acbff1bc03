#!/usr/bin/env bash
# README command 1: install dependencies, build in Release, run the main job on the bundled
# example database (examples/fabrics: three fabrics made by the project from known yarn models,
# and one real acrylic stockinette converted from the MIT-licensed stitch-by-stitch data):
# validate and list it, then `yarnfit batch` runs the whole pipeline on every fabric (shell
# fit to the stretch and pear-loop tests, uniform targets, yarn-level fit with the quick
# budget), once more on one fabric with the default budget, and `yarnfit report` compares the
# two runs (what accuracy costs); the yarn fits are compared with the yarn models the examples
# were made from, and every fit with the record's measured curves (end to end).
set -euo pipefail
# OpenMP threads spin while waiting by default; on a 2-core machine with other work running
# that slows the parallel energy loops 3-10x. Passive waiting gives the core back.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build-release -G Ninja -DCMAKE_BUILD_TYPE=Release -DYARNFIT_BUILD_TESTS=OFF -DYARNFIT_BUILD_BENCH=OFF
cmake --build build-release --parallel 2
yarnfit=./build-release/cli/yarnfit
db=examples/fabrics
out=build-release/example_output
$yarnfit db validate "$db"
$yarnfit db list "$db"
$yarnfit db show "$db/stockinette_demo"

echo
# The yarn stage's search comes in named budgets (quick, default, thorough: yarn_fit/fit/
# budget.hpp). Every fabric is fitted with the quick budget, and the first one again with the
# default budget; the report over both runs shows, in "What accuracy costs", what the larger
# search bought and what it cost.
quick="$out/budget-quick"
default="$out/budget-default"
rm -rf "$out"  # the example's own output folder: a fresh run each time
echo "== yarnfit batch $db --out $quick --budget quick"
$yarnfit batch "$db" --out "$quick" --budget quick
echo
echo "== yarnfit batch $db --out $default --budget default --only stockinette_demo"
$yarnfit batch "$db" --out "$default" --budget default --only stockinette_demo
echo
$yarnfit batch status "$quick"
echo
echo "== yarnfit report $quick $default --out $out/report"
$yarnfit report "$quick" "$default" --out "$out/report"
python3 - "$db" "$quick" "$default" "$out" <<'EOF'
import json, os, subprocess, sys
db, out, default, top = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
yarnfit = "./build-release/cli/yarnfit"
# The examples come from known yarn models (examples/make_example.cpp): each fit's yarn
# parameters beside them, its errors against its targets and end to end against the curves.
keys = ["ks1", "eps_s", "kb", "R1", "kc1"]
for fabric in sorted(os.listdir(os.path.join(out, "fabrics"))):
    shown = json.loads(subprocess.run([yarnfit, "db", "show", os.path.join(db, fabric), "--json"],
                                      capture_output=True, text=True, check=True).stdout)
    truth = shown.get("ground_truth") or {}
    shell_fit = json.load(open(os.path.join(out, "fabrics", fabric, "shell_fit.json")))
    shell, tested = shell_fit["errors"], [d for d in ("weft", "bias", "warp") if d in shell_fit["errors_by_direction"]]
    bending = f"{shell['bending_pct']:.2f} %" if shell.get("bending_pct") is not None else "no pear-loop tests"
    print(f"\n{fabric}: shell errors (mean |error| / mean |measured|): force {shell['stretch_force_pct']:.2f} %, "
          f"compression {shell['compression_pct']:.2f} %, pear-loop aspect ratio {bending}")
    for label, run in (("quick", out), ("default", default)):
        path = os.path.join(run, "fabrics", fabric, "yarn_fit.json")
        if not os.path.exists(path):
            continue
        y = json.load(open(path))
        e, t = y["errors"], y["timing_s"]["total"]
        print(f"  {label} budget, yarn fit {t:.0f} s")
        if truth:
            print(f"    {'parameter':<10} {'fitted':>12} {'ground truth':>13} {'difference':>11}")
            for k in keys:
                v, g = y["params"].get(k), truth.get(k)
                print(f"    {k:<10} {v:>12.4g} {g:>13.4g} {100 * (v / g - 1):>+10.1f} %")
        else:
            print("    a real knit (no ground truth): " +
                  ", ".join(f"{k} {y['params'].get(k):.4g}" for k in keys))
        bend = f", bending {e['bending_pct']:.1f} %" if e.get("bending_pct") is not None else ""
        print(f"    against the uniform targets: stress comfort range {e['stress_comfort_pct']:.1f} %, "
              f"compression {e['compression_pct']:.1f} %{bend}")
        measured = y.get("errors_vs_measured") or {}

        def figures(m):
            names = (("stretch_force_pct", "force"), ("compression_pct", "compression"),
                     ("bending_pct", "pear-loop aspect ratio"))
            return ", ".join(f"{label} {m[key]:.1f} %" for key, label in names if m.get(key) is not None)

        if (measured.get("all") or {}).get("stretch_force_pct") is not None:
            print("    end to end, against the record's curves: " + figures(measured["all"]))
        elif measured:
            # A direction whose test the fitted model could not simulate has no figure (why: summary.txt).
            shown = [f"{d} {figures(measured[d])}" for d in tested if figures(measured.get(d) or {})]
            missing = [d for d in tested if not figures(measured.get(d) or {})]
            text = "; ".join(shown) if shown else "no direction"
            if missing:
                text += f" (not simulated: {', '.join(missing)}; why in summary.txt)"
            print("    end to end, against the record's curves: " + text)
print(f"\nper fabric: {out}/fabrics/<id>/ (shell_fit.json, uniform_targets.csv, yarn_fit.json, summary.txt, tile.pyp, ...)")
print(f"ledger:     {out}/batch.db (sqlite3; schema in docs/batch.md)")
print(f"report:     open {os.path.abspath(os.path.join(top, 'report', 'index.html'))} in a browser "
      "(both runs; 'What accuracy costs' compares the budgets; fabrics.csv, families.csv and report.json beside it)")
EOF
