#!/usr/bin/env python3
"""Issue 48's synthetic recovery: `synth fabric` -> `fit` must find the yarn model again.

usage: synthetic_recovery.py YARNFIT MAKE_EXAMPLE WORK [--fabrics stockinette_demo,interlock_demo]
                             [--budget default] [--threads 2]

Writes the bundled examples afresh (MAKE_EXAMPLE --all WORK/db: records made from known yarn
models through synth fabric's path, examples/make_example.cpp), fits each with `yarnfit fit`
and prints, per fabric, every fitted yarn parameter against its truth and the goals of issue 48
(ks1, eps_s, kb, kc1 within 5 %, R1 within 1 %), the comfort-range stress error against the
targets (goal <= 2 %), the yarn bending error (goal <= 5 %), the end-to-end force error against
the record's curves, and the wall time of the whole fit (goal <= 300 s on 2 threads).
"""
import argparse
import json
import os
import subprocess
import sys
import time

GOALS = {"ks1": 5.0, "eps_s": 5.0, "kb": 5.0, "R1": 1.0, "kc1": 5.0}


def truth_of(yarnfit, record):
    shown = subprocess.run([yarnfit, "db", "show", record, "--json"], capture_output=True, text=True, check=True)
    return json.loads(shown.stdout)["ground_truth"]


def mark(value, goal):
    return "ok" if value is not None and abs(value) <= goal else "MISSED"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("yarnfit")
    ap.add_argument("make_example")
    ap.add_argument("work")
    ap.add_argument("--fabrics", default="stockinette_demo,interlock_demo")
    ap.add_argument("--budget", default="default")
    ap.add_argument("--threads", default="2")
    a = ap.parse_args()
    db = os.path.join(a.work, "db")
    subprocess.run([a.make_example, "--all", db], check=True, capture_output=True)
    print(f"{'fabric':<18} {'figure':<22} {'fitted':>12} {'truth':>12} {'error':>9}  goal")
    for fabric in a.fabrics.split(","):
        record = os.path.join(db, fabric)
        out = os.path.join(a.work, "fit_" + fabric)
        start = time.time()
        done = subprocess.run([a.yarnfit, "fit", record, "--out", out, "--budget", a.budget, "--threads", a.threads,
                               "--force", "-q"], capture_output=True, text=True)
        seconds = time.time() - start
        if done.returncode != 0:
            print(f"{fabric:<18} fit failed: {done.stderr.strip()[-300:]}")
            continue
        truth = truth_of(a.yarnfit, record)
        y = json.load(open(os.path.join(out, "yarn_fit.json")))
        for k, goal in GOALS.items():
            v, t = y["params"][k], truth[k]
            err = 100.0 * (v / t - 1.0)
            print(f"{fabric:<18} {k:<22} {v:>12.4g} {t:>12.4g} {err:>+8.1f} %  {goal:g} % {mark(err, goal)}")
        e = y["errors"]
        print(f"{fabric:<18} {'stress, comfort range':<22} {'':>12} {'':>12} {e['stress_comfort_pct']:>8.2f} %  2 % "
              f"{mark(e['stress_comfort_pct'], 2.0)}")
        if e.get("bending_pct") is not None:
            print(f"{fabric:<18} {'bending':<22} {'':>12} {'':>12} {e['bending_pct']:>8.2f} %  5 % {mark(e['bending_pct'], 5.0)}")
        m = (y.get("errors_vs_measured") or {}).get("all") or {}
        if m.get("stretch_force_pct") is not None:
            print(f"{fabric:<18} {'end to end, force':<22} {'':>12} {'':>12} {m['stretch_force_pct']:>8.2f} %")
        print(f"{fabric:<18} {'wall time':<22} {'':>12} {'':>12} {seconds:>7.0f} s  300 s {mark(seconds, 300.0)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
