#!/usr/bin/env python3
"""Issue 48's goal table on the four real acrylic knits: the yarn fit as a user runs it.

usage: acrylic_goals.py YARNFIT WORK [--knits stockinette,garter,rib,seed] [--threads 2]
                        [--label NAME] [--extra "ARGS"]

Builds the acrylic records (scripts/build_acrylic_records.py --generated-tiles, into WORK),
fits the shell stage once per knit (kept in WORK/shell_<knit>), then `yarn fit` on its targets
with the default settings (plus --extra), and prints per knit and direction: the yarn model's
comfort-range stress error against the targets (the goal: <= 10 %), its compression error
beside it, the end-to-end error against the measured curves (the homogenised law run through
the record's clamped-stretch tests: stretch_force_pct; goal <= 15 %), the fitted shape, what
sits on a bound, and the yarn fit's time (goal <= 120 s). A YARNFIT without the check (an older
build) shows "n/a" there. Run two builds into the same WORK to compare them in one sitting.
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def run(args):
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(args)}: exit {done.returncode}\n{done.stderr[-2000:]}")
    return done


def pct(v):
    return "n/a" if v is None else f"{v:.1f} %"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("yarnfit")
    ap.add_argument("work")
    ap.add_argument("--knits", default="stockinette,garter,rib,seed")
    ap.add_argument("--threads", default="2")
    ap.add_argument("--label", default="")
    ap.add_argument("--extra", default="")
    a = ap.parse_args()
    yarnfit, work = os.path.abspath(a.yarnfit), os.path.abspath(a.work)
    label = a.label or os.path.basename(os.path.dirname(os.path.dirname(yarnfit)))
    records = os.path.join(work, "records")
    if not os.path.isdir(records):
        subprocess.run([sys.executable, os.path.join(REPO, "scripts", "build_acrylic_records.py"), records,
                        "--generated-tiles"], check=True, capture_output=True)
    rows = []
    for knit in a.knits.split(","):
        record = os.path.join(records, f"acrylic_{knit}")
        shell = os.path.join(work, f"shell_{knit}")
        if not os.path.exists(os.path.join(shell, "uniform_targets.csv")):
            run([yarnfit, "shell", "fit", record, "--out", shell, "--quiet"])
        out = os.path.join(work, f"goals_{label}", knit)
        subprocess.run(["rm", "-rf", out], check=True)
        t0 = time.time()
        done = run([yarnfit, "yarn", "fit", record, "--targets", os.path.join(shell, "uniform_targets.csv"), "--out", out,
                    "--threads", a.threads, "--quiet"] + shlex.split(a.extra))
        wall = time.time() - t0
        try:
            j = json.load(open(os.path.join(out, "yarn_fit.json")))
        except OSError:
            print(f"{knit}: no yarn_fit.json ({done.stderr.strip()[-300:]})", flush=True)
            continue
        by = j.get("errors_by_direction", {})
        vs = j.get("errors_vs_measured") or {}
        shape = j.get("shape")
        row = {
            "knit": knit,
            "comfort": {d: by.get(d, {}).get("stress_comfort_pct") for d in ("weft", "warp")},
            "compression": {d: by.get(d, {}).get("compression_pct") for d in ("weft", "warp")},
            "measured": {d: (vs.get(d) or {}).get("stretch_force_pct") if vs else None for d in ("weft", "warp")},
            "shape": f"{shape['aspect']:.3f} (prior {shape['prior']:.3f}, {len(shape['trials'])} trials)" if shape else "–",
            "bound": ", ".join(j.get("on_bound", [])) or "–",
            "yarn_s": j["timing_s"]["total"] if not shape else shape["seconds"],
            "wall_s": wall,
        }
        rows.append(row)
        print(json.dumps(row), flush=True)
    print(f"\n{label}: yarn fit of the acrylic knits (weft / warp)")
    print("| knit | comfort stress vs targets | compression vs targets | force vs measured (end to end) | shape | on a bound | yarn fit | wall |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['knit']} | {pct(r['comfort']['weft'])} / {pct(r['comfort']['warp'])} | "
              f"{pct(r['compression']['weft'])} / {pct(r['compression']['warp'])} | "
              f"{pct(r['measured']['weft'])} / {pct(r['measured']['warp'])} | {r['shape']} | {r['bound']} | "
              f"{r['yarn_s']:.0f} s | {r['wall_s']:.0f} s |")
    met = sum(1 for r in rows for d in ("weft", "warp") if r["comfort"][d] is not None and r["comfort"][d] <= 10.0)
    print(f"goal comfort <= 10 %: {met} of {2 * len(rows)} directions; "
          f"yarn fit <= 120 s: {sum(1 for r in rows if r['yarn_s'] <= 120)} of {len(rows)} knits")


if __name__ == "__main__":
    main()
