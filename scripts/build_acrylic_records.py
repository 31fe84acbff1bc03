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

With --pattern PYP (a periodic yarn tile of a stockinette, e.g.
../shared/data/patterns/stockinette.pyp) the stockinette record also gets a tile:

    OUT/acrylic_stockinette/tile.pyp      <- PYP scaled uniformly (written outside the repository)
    fabric.yaml: pattern: {file: tile.pyp, weft_axis: <the axis the tile's yarns run along>}

The option applies to the stockinette record only; garter, rib and seed keep no pattern
(none of the shared tiles is one of those knits). The tile is scaled so that its yarn
length per stitch equals the acrylic stockinette's stitch length, 11.28 mm (data README,
"Yarn and stitch facts"):
  * stitches in the tile: the yarns of a weft knit run along the courses (their net period
    offset lies along one lattice axis: the weft axis); each loop takes the yarn once up
    the wale axis and back, so the loops of a yarn are counted as the up-crossings of its
    mean wale coordinate (with a hysteresis of a quarter of its wale extent); the tile's
    stitches are the sum over its yarns.
  * yarn length per stitch: the sum of the *RL rest lengths (the yarn's own length; the
    polyline length is printed beside it) over the stitches.
  * scaling: *pattern px py radius, *Q x y z and *RL scale by the factor; the *Q twist,
    *RK (integrated, dimensionless DER curvature binormals: fabrics_db/tile/periodic_tile.hpp),
    *RT and *RefT (angles) and *RefD1 (unit directors) stay as they are.
  * the stitch length is matched and the radius follows the scale: it is printed and
    written into the record's description beside the reported effective radius, 0.74 mm.

With --generated-tiles every record names a tile for yarnfit to generate from its knit
(issue 20; `yarnfit tile make`), with the stitch length and effective yarn radius of the data
README's "Yarn and stitch facts" (the stitch-by-stitch simulations' values):

    fabric.yaml: pattern: {knit: <chart>, stitch_length_mm: L, yarn_radius_mm: R}

    stockinette  stockinette  11.28 mm  0.74 mm      rib   rib1x1  16.10 mm  1.18 mm
    garter       garter       10.55 mm  0.54 mm      seed  seed    15.67 mm  1.20 mm

(the stitch-by-stitch rib model, rib.py, is a 1x1 rib). With both options the stockinette
keeps the scaled file and the others get generated tiles.

With --only KNIT only that knit's record is written. With --example (and --only) the record
is the bundled example's real knit (SPEC section 6 allows the bundled example one real knit
converted by the project, attributed in its record): OUT may then be the repository's
examples/fabrics, the record's description cites the paper, the repository, its commit and
its MIT licence, and the licence's text goes beside it as LICENSE-stitch-by-stitch.txt.
README command 1 fits it beside the examples made from known yarn models:

    python3 scripts/build_acrylic_records.py examples/fabrics --only stockinette \
        --generated-tiles --example --force

Usage: build_acrylic_records.py OUT [--shared DIR] [--pattern PYP] [--generated-tiles]
       [--only KNIT] [--example] [--force]
Exit codes: 0 written, 2 bad input or refusal (existing output without --force, output
inside the source tree, missing data).
"""

import argparse
import csv
import math
import os
import re
import statistics
import sys

KNITS = ["garter", "rib", "seed", "stockinette"]
SAMPLES = {"x": "weft", "y": "warp"}
DENIER = 4515
STIFFNESS_N = 400.0
STOCKINETTE_STITCH_LENGTH_MM = 11.28    # data README, "Yarn and stitch facts"
# knit -> (chart, stitch length mm, effective yarn radius mm), data README "Yarn and stitch facts"
GENERATED_TILES = {"stockinette": ("stockinette", 11.28, 0.74), "garter": ("garter", 10.55, 0.54),
                   "rib": ("rib1x1", 16.10, 1.18), "seed": ("seed", 15.67, 1.20)}
STOCKINETTE_EFFECTIVE_RADIUS_MM = 0.74
STOCKINETTE_CORE_RADIUS_MM = 0.325
# pyp sections in file order: (name, columns, which columns are lengths)
PYP_SECTIONS = [("pattern", 4, {0, 1, 2}), ("Q", 4, {0, 1, 2}), ("E", 4, set()), ("RL", 1, {0}),
                ("RK", 2, set()), ("RT", 1, set()), ("RefD1", 3, set()), ("RefT", 1, set())]
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The source of the measurements, cited in every record --example writes.
SOURCE_COMMIT = "0ed27f35dcf5c3bda874f214bbcab0455055edf0"
ATTRIBUTION = ("Data: K. Singal, M. S. Dimitriyev, S. E. Gonzalez, S. Quinn, E. A. Matsumoto, "
               "'Programming mechanics in knitted materials, stitch by stitch', repository "
               f"github.com/sabetta/stitch-by-stitch (commit {SOURCE_COMMIT[:7]}), MIT licence "
               "(LICENSE-stitch-by-stitch.txt beside this record); converted by "
               "scripts/build_acrylic_records.py.")
# The source repository's licence, which the MIT terms ask to travel with the data.
MIT_LICENCE = """MIT License

Copyright (c) 2023 sabetta

Permission is hereby granted, free of charge, to any person obtaining a copy
of this software and associated documentation files (the "Software"), to deal
in the Software without restriction, including without limitation the rights
to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
copies of the Software, and to permit persons to whom the Software is
furnished to do so, subject to the following conditions:

The above copyright notice and this permission notice shall be included in all
copies or substantial portions of the Software.

THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
SOFTWARE.
"""


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


def read_pyp(path):
    """Sections of a pyp tile: {name: {"header": line, "rows": [[str, ...]], "lines": [n]}}."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except OSError as e:
        fail(f"{path}: cannot read the tile ({e.strerror})")
    known = {name: cols for name, cols, _ in PYP_SECTIONS}
    sections, cur = {}, None
    for n, line in enumerate(lines, 1):
        body = line.split("#", 1)[0].strip()
        if line.startswith("*"):
            cur = line[1:].split()[0] if line[1:].split() else ""
            if cur not in known:
                fail(f"{path}:{n}: *{cur}: unknown section; this script scales only "
                     + ", ".join("*" + k for k in known))
            if cur in sections:
                fail(f"{path}:{n}: *{cur}: section repeated")
            sections[cur] = {"header": line.rstrip(), "rows": [], "lines": []}
        elif body:
            if cur is None:
                fail(f"{path}:{n}: values before the first section")
            row = body.split()
            if len(row) != known[cur]:
                fail(f"{path}:{n}: *{cur}: expected {known[cur]} values, got {len(row)}")
            try:
                [float(v) for v in row]
            except ValueError:
                fail(f"{path}:{n}: *{cur}: not a number in {body!r}")
            sections[cur]["rows"].append(row)
            sections[cur]["lines"].append(n)
    for name in ("pattern", "Q", "E"):
        if name not in sections:
            fail(f"{path}: no *{name} section")
    if len(sections["pattern"]["rows"]) != 1:
        fail(f"{path}: *pattern: expected one row (px py radius n)")
    nv = len(sections["Q"]["rows"])
    for name, rows in ((k, v["rows"]) for k, v in sections.items() if k != "pattern"):
        if len(rows) != nv:
            fail(f"{path}: *{name}: {len(rows)} rows for {nv} vertices")
    return sections


def tile_yarns(sections):
    """Each periodic yarn of the tile: (net offset (dx, dy), rest length, polyline length,
    points unrolled along the yarn)."""
    px, py = (float(v) for v in sections["pattern"]["rows"][0][:2])
    q = [[float(v) for v in r[:3]] for r in sections["Q"]["rows"]]
    edges = [[int(float(v)) for v in r] for r in sections["E"]["rows"]]
    rl = [float(r[0]) for r in sections["RL"]["rows"]] if "RL" in sections else None
    out_edge = {}
    for i, (v0, v1, dx, dy) in enumerate(edges):
        if v0 in out_edge or not (0 <= v0 < len(q) and 0 <= v1 < len(q)):
            fail("tile: *E: every vertex needs exactly one outgoing edge inside the tile")
        out_edge[v0] = i
    seen, yarns = set(), []
    for start in range(len(q)):
        if start in seen:
            continue
        v, ox, oy, rest, geo, pts = start, 0, 0, 0.0, 0.0, []
        while True:
            if v in seen:
                fail("tile: *E: the edges do not form closed yarns")
            seen.add(v)
            i = out_edge.get(v)
            if i is None:
                fail(f"tile: *E: vertex {v} has no outgoing edge")
            _, v1, dx, dy = edges[i]
            a = [q[v][0] + ox * px, q[v][1] + oy * py, q[v][2]]
            ox, oy = ox + dx, oy + dy
            b = [q[v1][0] + ox * px, q[v1][1] + oy * py, q[v1][2]]
            pts.append(a)
            geo += math.dist(a, b)
            rest += rl[i] if rl is not None else math.dist(a, b)
            v = v1
            if v == start:
                break
        yarns.append(((ox, oy), rest, geo, pts))
    return yarns


def count_loops(points, axis):
    """Loops of one course yarn over its period: up-crossings of its mean coordinate along
    the wale axis, with a hysteresis of a quarter of the yarn's extent along that axis."""
    w = [p[axis] for p in points]
    mean, band = statistics.fmean(w), 0.25 * (max(w) - min(w))
    if band <= 0.0:
        return 0
    # start from a point clearly below the mean, then walk the closed yarn once
    start = min(range(len(w)), key=lambda i: w[i])
    state, loops = "low", 0
    for k in range(1, len(w) + 1):
        y = w[(start + k) % len(w)]
        if state == "low" and y > mean + band:
            state, loops = "high", loops + 1
        elif state == "high" and y < mean - band:
            state = "low"
    return loops


def scaled_stockinette_tile(pyp):
    """The tile `pyp` scaled to the acrylic stockinette stitch length: the figures for the
    record and the printout, and the scaled file's text under "text"."""
    sections = read_pyp(pyp)
    yarns = tile_yarns(sections)
    offsets = {off for off, *_ in yarns}
    if any(off == (0, 0) for off in offsets) or not (
            all(dy == 0 for _, dy in offsets) or all(dx == 0 for dx, _ in offsets)):
        fail(f"{pyp}: the yarns do not all run along one tile axis (net offsets "
             f"{sorted(offsets)}); expected the course yarns of a weft knit")
    weft = "x" if all(dy == 0 for _, dy in offsets) else "y"
    wale_index = 1 if weft == "x" else 0
    loops = [count_loops(pts, wale_index) for _, _, _, pts in yarns]
    stitches = sum(loops)
    if stitches == 0:
        fail(f"{pyp}: no loops found along the yarns")
    rest = sum(r for _, r, _, _ in yarns)
    geo = sum(g for _, _, g, _ in yarns)
    per_stitch = rest / stitches
    factor = STOCKINETTE_STITCH_LENGTH_MM * 1e-3 / per_stitch

    lengths = {name: cols for name, _, cols in PYP_SECTIONS}
    with open(pyp, encoding="utf-8") as f:
        lines = f.read().splitlines()
    row_at = {}
    for name, sec in sections.items():
        for row, n in zip(sec["rows"], sec["lines"]):
            row_at[n] = (name, row)
    out = [f"# {os.path.basename(pyp)} scaled by {factor:.9g} by scripts/build_acrylic_records.py: "
           f"yarn length per stitch {1e3 * per_stitch:.6g} mm -> {STOCKINETTE_STITCH_LENGTH_MM} mm"]
    for n, line in enumerate(lines, 1):
        if n not in row_at:
            out.append(line)
            continue
        name, row = row_at[n]
        out.append(" ".join(f"{float(v) * factor:.9g}" if c in lengths[name] else v
                            for c, v in enumerate(row)))

    px, py, radius = (float(v) for v in sections["pattern"]["rows"][0][:3])
    return {
        "source": pyp, "weft": weft, "yarns": len(yarns), "loops": loops, "stitches": stitches,
        "rest": rest, "geo": geo, "per_stitch": per_stitch, "factor": factor,
        "radius": radius, "px": px, "py": py,
        "scaled_radius": radius * factor, "scaled_px": px * factor, "scaled_py": py * factor,
        "scaled_per_stitch": per_stitch * factor, "text": "\n".join(out) + "\n",
    }


def pattern_note(t):
    return (f"Pattern: tile.pyp is {os.path.basename(t['source'])} ({t['stitches']} stitches: "
            f"{t['yarns']} course yarns along {t['weft']}) scaled uniformly by {t['factor']:.4f} so that "
            f"its yarn length per stitch (rest lengths) is the acrylic stockinette's "
            f"{STOCKINETTE_STITCH_LENGTH_MM} mm; the stitch length is matched and the radius follows: "
            f"{1e3 * t['scaled_radius']:.3f} mm against the reported effective radius "
            f"{STOCKINETTE_EFFECTIVE_RADIUS_MM} mm (core {STOCKINETTE_CORE_RADIUS_MM} mm); period "
            f"{1e3 * t['scaled_px']:.3f} x {1e3 * t['scaled_py']:.3f} mm.")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", help="folder to write the fabric records into (outside the repository)")
    ap.add_argument("--shared", default=os.path.join(REPO, "..", "shared"), help="the shared/ folder")
    ap.add_argument("--pattern", metavar="PYP",
                    help="stockinette tile to scale into OUT/acrylic_stockinette/tile.pyp "
                         "(stockinette record only)")
    ap.add_argument("--generated-tiles", action="store_true",
                    help="every record names a knit tile for yarnfit to generate (pattern: {knit: ...})")
    ap.add_argument("--only", choices=KNITS, help="write only this knit's record")
    ap.add_argument("--example", action="store_true",
                    help="the bundled example's real knit: attributed, licence beside it; OUT may be "
                         "the repository's examples/fabrics (needs --only)")
    ap.add_argument("--force", action="store_true", help="replace records written before")
    a = ap.parse_args()
    if a.example and not a.only:
        fail("--example writes one record: name it with --only KNIT")

    src = os.path.join(a.shared, "data", "measured", "stitch-by-stitch", "acrylic")
    if not os.path.isdir(src):
        fail(f"{src}: no such folder (the acrylic measurements are read from ../shared at run time)")
    out = os.path.abspath(a.out)
    examples = os.path.join(REPO, "examples", "fabrics")
    if os.path.commonpath([out, REPO]) == REPO and not (a.example and out == examples):
        fail(f"{out}: inside the source tree; write the records to a scratch folder outside it")

    samples = {(k, ax): read_sample(src, k, ax) for k in KNITS for ax in SAMPLES}
    consistent = [s["fabric_width"] / s["gauge_width"] for s in samples.values()
                  if s["fabric_width"] >= s["gauge_width"]]
    width_ratio = statistics.median(consistent)
    # read and scale the tile before any record is written
    stockinette_tile = scaled_stockinette_tile(a.pattern) if a.pattern else None

    for knit in [a.only] if a.only else KNITS:
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
        tile = stockinette_tile if knit == "stockinette" else None
        if tile:
            with open(os.path.join(folder, "tile.pyp"), "w", encoding="utf-8") as f:
                f.write(tile["text"])
        family = samples[(knit, "x")]["family"]
        description = (f"Acrylic {knit} (Brava worsted), stitch-by-stitch uniaxial tests: X sample "
                       f"as weft, Y sample as warp; merged medians of the repeats.")
        if notes:
            description += " " + " ".join(n[0].upper() + n[1:] + "." for n in notes)
        if tile:
            description += " " + pattern_note(tile)
        if a.example:
            description += " " + ATTRIBUTION
            with open(os.path.join(folder, "LICENSE-stitch-by-stitch.txt"), "w", encoding="utf-8") as f:
                f.write(MIT_LICENCE)
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
            + (f"pattern: {{file: tile.pyp, weft_axis: {tile['weft']}}}   # scaled by "
               f"{tile['factor']:.6g} from {os.path.basename(tile['source'])}\n" if tile else "")
            + (f"pattern: {{knit: {GENERATED_TILES[knit][0]}, stitch_length_mm: {GENERATED_TILES[knit][1]}, "
               f"yarn_radius_mm: {GENERATED_TILES[knit][2]}}}   # generated by yarnfit (data README)\n"
               if a.generated_tiles and not tile else "")
            + "stretch_tests:\n" + "".join(tests))
        with open(os.path.join(folder, "fabric.yaml"), "w", encoding="utf-8") as f:
            f.write(text)
        print(f"wrote {folder}" + (f" ({len(notes)} estimated width)" if notes else ""))
        if tile:
            t = tile
            print(f"  tile.pyp from {t['source']}: weft axis {t['weft']}, {t['yarns']} yarns, loops per yarn "
                  f"{t['loops']} -> {t['stitches']} stitches\n"
                  f"  yarn length per stitch {1e3 * t['per_stitch']:.4f} mm (rest lengths; polyline "
                  f"{1e3 * t['geo'] / t['stitches']:.4f} mm) -> {1e3 * t['scaled_per_stitch']:.4f} mm\n"
                  f"  scale factor {t['factor']:.6f}\n"
                  f"  period {1e3 * t['px']:.4f} x {1e3 * t['py']:.4f} mm -> "
                  f"{1e3 * t['scaled_px']:.4f} x {1e3 * t['scaled_py']:.4f} mm\n"
                  f"  radius {1e3 * t['radius']:.4f} mm -> {1e3 * t['scaled_radius']:.4f} mm; reported "
                  f"effective radius {STOCKINETTE_EFFECTIVE_RADIUS_MM} mm (scaled/reported = "
                  f"{1e3 * t['scaled_radius'] / STOCKINETTE_EFFECTIVE_RADIUS_MM:.3f}; core "
                  f"{STOCKINETTE_CORE_RADIUS_MM} mm): stitch length matched, radius follows the scale")
    return 0


if __name__ == "__main__":
    sys.exit(main())
