#!/usr/bin/env python3
"""Build yarnfit fabric records from the stitch-by-stitch acrylic measurements.

Reads ../shared/data/measured/stitch-by-stitch/acrylic (never copies it into the
repository) and writes, in a scratch folder OUTSIDE the source tree, one fabric folder per
knit (garter, rib, seed, stockinette):

    OUT/acrylic_<knit>/fabric.yaml
    OUT/acrylic_<knit>/stretch_weft.csv   <- the X sample (course direction)
    OUT/acrylic_<knit>/stretch_warp.csv   <- the Y sample (wale direction)

Each test gets its own swatch (free length between the clamps, fabric width) and gauge
marks (pin spacing along and across the pull) from the sample's YAML, and its curve from
the merged CSV (medians across repeats; the spread columns are kept as extra columns).

Assumptions, stated because the source does not give them:
  * X = course = weft, Y = wale = warp (the data README's convention).
  * Yarn: KnitPicks Brava Worsted, 100 % acrylic, 218 yd per 100 g => 0.5017 g/m =>
    4515 denier. Spun yarn: no filament count.
  * Yarn stretch stiffness: no yarn tensile test is published. A spun acrylic of about
    5000 dtex with a typical tenacity near 2 cN/dtex breaks near 100 N at about 25 %
    extension, i.e. a secant stiffness of about 400 N per unit strain; 400 N is used.
  * Where the recorded fabric width at the clamp is narrower than the pin spacing (garter
    X, whose width the data README calls doubtful, and seed Y), the recorded value cannot
    be the free-edge width; the width is then estimated as pin spacing x the median
    width/pin-spacing ratio of the samples whose values are consistent, and the record's
    description says so.

Usage: build_acrylic_records.py OUT [--shared DIR] [--force]
Exit codes: 0 written, 2 bad input or refusal (existing output without --force, output
inside the source tree, missing data).
"""

import argparse
import csv
import os
import re
import statistics
import sys

KNITS = ["garter", "rib", "seed", "stockinette"]
SAMPLES = {"x": "weft", "y": "warp"}
DENIER = 4515
STIFFNESS_N = 400.0
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def fail(msg):
    print(f"build_acrylic_records: {msg}", file=sys.stderr)
    sys.exit(2)


def yaml_value(path, key):
    """Value of an indented 'key: value' line of the generated sample YAML."""
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            m = re.match(rf"^\s*{re.escape(key)}:\s*(.+?)\s*$", line)
            if m:
                return m.group(1).strip('"'), n
    fail(f"{path}: field {key} not found")


def number(path, key):
    text, line = yaml_value(path, key)
    try:
        return float(text)
    except ValueError:
        fail(f"{path}:{line}: {key}: expected a number, got {text!r}")


def read_sample(src, knit, axis):
    stem = os.path.join(src, f"{knit}_{axis}")
    y = stem + ".yaml"
    return {
        "yaml": y,
        "csv": stem + "_merged.csv",
        "family": yaml_value(y, "family")[0],
        "gauge_length": number(y, "undeformed_gauge_length_mm"),
        "gauge_width": number(y, "undeformed_gauge_width_mm"),
        "clamp_length": number(y, "undeformed_clamp_separation_mm"),
        "fabric_width": number(y, "fabric_width_at_clamp_mm"),
    }


def write_curve(sample, out_csv):
    with open(sample["csv"], newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    first = ["stretch", "force_N", "compression"]
    rest = [c for c in rows[0].keys() if c not in first] if rows else []
    with open(out_csv, "w", newline="", encoding="utf-8") as f:
        f.write(f"# from {os.path.basename(sample['csv'])} (stitch-by-stitch, merged repeats)\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(first + rest)
        for r in rows:
            w.writerow([r[c] for c in first + rest])
    return len(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", help="folder to write the fabric records into (outside the repository)")
    ap.add_argument("--shared", default=os.path.join(REPO, "..", "shared"), help="the shared/ folder")
    ap.add_argument("--force", action="store_true", help="replace records written before")
    a = ap.parse_args()

    src = os.path.join(a.shared, "data", "measured", "stitch-by-stitch", "acrylic")
    if not os.path.isdir(src):
        fail(f"{src}: no such folder (the acrylic measurements are read from ../shared at run time)")
    out = os.path.abspath(a.out)
    if os.path.commonpath([out, REPO]) == REPO:
        fail(f"{out}: inside the source tree; write the records to a scratch folder outside it")

    samples = {(k, ax): read_sample(src, k, ax) for k in KNITS for ax in SAMPLES}
    consistent = [s["fabric_width"] / s["gauge_width"] for s in samples.values()
                  if s["fabric_width"] >= s["gauge_width"]]
    width_ratio = statistics.median(consistent)

    for knit in KNITS:
        folder = os.path.join(out, f"acrylic_{knit}")
        if os.path.exists(os.path.join(folder, "fabric.yaml")) and not a.force:
            fail(f"{folder}: a record exists already; pass --force to replace it")
        os.makedirs(folder, exist_ok=True)
        tests, notes = [], []
        for axis, direction in SAMPLES.items():
            s = samples[(knit, axis)]
            width = s["fabric_width"]
            if width < s["gauge_width"]:
                width = round(s["gauge_width"] * width_ratio, 2)
                notes.append(
                    f"{direction} swatch width estimated as {width} mm: the recorded width at the "
                    f"clamp ({s['fabric_width']} mm) is narrower than the pin spacing "
                    f"({s['gauge_width']} mm); pin spacing x {width_ratio:.4f}, the median ratio of "
                    f"the consistent samples")
            n = write_curve(s, os.path.join(folder, f"stretch_{direction}.csv"))
            tests.append(
                f"  {direction}:   # {os.path.basename(s['yaml'])}, {n} points\n"
                f"    file: stretch_{direction}.csv\n"
                f"    swatch: {{length_mm: {s['clamp_length']}, width_mm: {width}}}\n"
                f"    gauge: {{length_mm: {s['gauge_length']}, width_mm: {s['gauge_width']}}}\n")
        family = samples[(knit, "x")]["family"]
        description = (f"Acrylic {knit} (Brava worsted), stitch-by-stitch uniaxial tests: X sample "
                       f"as weft, Y sample as warp; merged medians of the repeats.")
        if notes:
            description += " " + " ".join(n[0].upper() + n[1:] + "." for n in notes)
        text = (
            "# Built by scripts/build_acrylic_records.py from "
            "shared/data/measured/stitch-by-stitch/acrylic\n"
            "# (sabetta/stitch-by-stitch, MIT licence). Assumptions are listed in the script.\n"
            f"id: acrylic_{knit}\n"
            f"family: {family}\n"
            f"description: \"{description}\"\n"
            "yarns:\n"
            "  - material: acrylic\n"
            f"    denier: {DENIER}          # 218 yd per 100 g (Brava worsted)\n"
            "    mass_fraction: 1.0\n"
            f"    stiffness_N: {STIFFNESS_N}    # assumed; no yarn tensile test is published\n"
            "stretch_tests:\n" + "".join(tests))
        with open(os.path.join(folder, "fabric.yaml"), "w", encoding="utf-8") as f:
            f.write(text)
        print(f"wrote {folder}" + (f" ({len(notes)} estimated width)" if notes else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
