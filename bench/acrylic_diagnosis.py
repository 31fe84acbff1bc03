#!/usr/bin/env python3
"""Where the yarn fit's misses on the four real acrylic knits come from (issue 48, item 6).

usage: acrylic_diagnosis.py YARNFIT WORK [--knits stockinette,garter,rib,seed]
                            [--aspect-factors 0.8,0.9,1,1.1,1.2] [--threads 2] [--skip-sweep]
                            [--skip-variants]

Builds the acrylic records (scripts/build_acrylic_records.py --generated-tiles, into WORK,
never into the repository), fits the shell stage once per knit, and then, on the same uniform
targets, the yarn stage several ways:
  default      `yarn fit` as a user runs it (the tile generated from stitch length and radius,
               its period relaxed by the mechanics);
  stress only  the same with --compression-weight 0;
  aspect f     the tile generated at a held period: the default tile's wale spacing w and a
               course spacing f times its own, given as the record's knitting_gauge.
It prints, per knit and direction: the shell stage's own error against the measured curves
over the comfort range (force per width up to 33.3 N/m: mean |F_sim - F_meas| over the largest
measured force there), and the yarn model's comfort-range stress error against the targets
(and its compression error) for each variant, with its time.
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
COMFORT = 100.0 / 3.0  # N/m


def run(args, **kw):
    done = subprocess.run(args, capture_output=True, text=True, **kw)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(args)}: exit {done.returncode}\n{done.stderr[-3000:]}")
    return done.stdout


def swatch_widths(record):
    """Each stretch test's swatch width [m] from fabric.yaml (the records this script builds)."""
    text = open(os.path.join(record, "fabric.yaml")).read()
    widths = {}
    for direction in ("weft", "warp", "bias"):
        m = re.search(rf"^  {direction}:.*?\n    swatch: {{length_mm: [0-9.]+, width_mm: ([0-9.]+)}}", text, re.M | re.S)
        if m:
            widths[direction] = float(m.group(1)) * 1e-3
    return widths


def shell_comfort_errors(shell_dir, record):
    """The shell law's comfort-range force error against the measured curve, per direction [%]."""
    widths = swatch_widths(record)
    rows = {}
    with open(os.path.join(shell_dir, "shell_curves.csv")) as f:
        for r in csv.DictReader(f):
            rows.setdefault(r["direction"], []).append(r)
    out = {}
    for d, rs in rows.items():
        w = widths[d]
        inside = [r for r in rs if float(r["measured_force_N"]) / w <= COMFORT]
        if not inside:
            continue
        top = max(float(r["measured_force_N"]) for r in inside)
        err = sum(abs(float(r["simulated_force_N"]) - float(r["measured_force_N"])) for r in inside) / len(inside)
        out[d] = 100.0 * err / top
    return out


def yarn_errors(out_dir):
    j = json.load(open(os.path.join(out_dir, "yarn_fit.json")))
    by = j.get("errors_by_direction", {})
    return ({d: (e.get("stress_comfort_pct"), e.get("compression_pct")) for d, e in by.items()},
            j["timing_s"]["total"], j.get("on_bound", []))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("yarnfit")
    ap.add_argument("work")
    ap.add_argument("--knits", default="stockinette,garter,rib,seed")
    ap.add_argument("--aspect-factors", default="0.8,0.9,1,1.1,1.2")
    ap.add_argument("--threads", default="2")
    ap.add_argument("--skip-sweep", action="store_true")
    ap.add_argument("--skip-variants", action="store_true", help="only the aspect sweep")
    a = ap.parse_args()
    yarnfit = os.path.abspath(a.yarnfit)
    work = os.path.abspath(a.work)
    os.makedirs(work, exist_ok=True)
    records = os.path.join(work, "records")
    if not os.path.isdir(records):
        run([sys.executable, os.path.join(REPO, "scripts", "build_acrylic_records.py"), records, "--generated-tiles"])
    table = []
    for knit in a.knits.split(","):
        record = os.path.join(records, f"acrylic_{knit}")
        shell_dir = os.path.join(work, f"shell_{knit}")
        if not os.path.exists(os.path.join(shell_dir, "uniform_targets.csv")):
            run([yarnfit, "shell", "fit", record, "--out", shell_dir, "--quiet"])
        targets = os.path.join(shell_dir, "uniform_targets.csv")
        shell = shell_comfort_errors(shell_dir, record)
        variants = [] if a.skip_variants else [("default", record, []),
                                               ("stress only", record, ["--compression-weight", "0"])]
        if not a.skip_sweep:
            pattern = re.search(r"pattern: \{knit: (\S+), stitch_length_mm: ([0-9.]+), yarn_radius_mm: ([0-9.]+)\}",
                                open(os.path.join(record, "fabric.yaml")).read())
            chart, length, radius = pattern.group(1), pattern.group(2), pattern.group(3)
            free = json.loads(run([yarnfit, "tile", "make", "--chart", chart, "--stitch-length-mm", length,
                                   "--yarn-radius-mm", radius, "--out", os.path.join(work, f"free_{knit}.pyp"),
                                   "--force", "--json"]))
            w, p = free["wale_spacing_mm"], free["course_spacing_mm"]
            print(f"{knit}: the default tile's spacings: wales {w:.3f} mm, courses {p:.3f} mm "
                  f"(aspect {p / w:.3f})", flush=True)
            for factor in (float(x) for x in a.aspect_factors.split(",")):
                aspect = factor * p / w
                folder = os.path.join(work, "records_aspect", f"{knit}_{aspect:.3f}")
                if os.path.isdir(folder):
                    shutil.rmtree(folder)
                shutil.copytree(record, folder)
                yaml = os.path.join(folder, "fabric.yaml")
                text = open(yaml).read()
                text += f"knitting_gauge: {{courses_per_10cm: {100.0 / (aspect * w):.6g}, wales_per_10cm: {100.0 / w:.6g}}}\n"
                open(yaml, "w").write(text)
                variants.append((f"aspect {aspect:.3f}", folder, []))
        for name, folder, extra in variants:
            out = os.path.join(work, "fits", f"{knit}_{name.replace(' ', '_')}")
            if os.path.isdir(out):
                shutil.rmtree(out)
            t0 = time.time()
            try:
                run([yarnfit, "yarn", "fit", folder, "--targets", targets, "--out", out, "--threads", a.threads,
                     "--quiet"] + extra)
                errors, seconds, on_bound = yarn_errors(out)
            except RuntimeError as e:
                print(f"{knit} {name}: FAILED {str(e).splitlines()[-1]}", flush=True)
                errors, seconds, on_bound = {}, time.time() - t0, ["failed"]
            row = (knit, name, shell, errors, seconds, on_bound)
            table.append(row)
            print(format_row(row), flush=True)
    print()
    print("| knit | variant | shell vs measured, comfort (weft / warp) | yarn vs targets, comfort stress (weft / warp) "
          "| yarn compression (weft / warp) | yarn fit time | on a bound |")
    print("|---|---|---|---|---|---|---|")
    for row in table:
        print(format_row(row))


def pct(v):
    return "–" if v is None else f"{v:.1f} %"


def format_row(row):
    knit, name, shell, errors, seconds, on_bound = row
    s = " / ".join(pct(shell.get(d)) for d in ("weft", "warp"))
    y = " / ".join(pct(errors.get(d, (None, None))[0]) for d in ("weft", "warp"))
    c = " / ".join(pct(errors.get(d, (None, None))[1]) for d in ("weft", "warp"))
    return f"| {knit} | {name} | {s} | {y} | {c} | {seconds:.0f} s | {', '.join(on_bound) or '–'} |"


if __name__ == "__main__":
    main()
