#!/usr/bin/env python3
"""The HTML report as a browser shows it (issue 19, acceptance 2).

Makes a small database with `yarnfit synth shell` (three fabrics in two families, one with
pear-loop tests), fits it with `yarnfit batch --stages shell` (which writes DIR/report/), and
a report of 30 fabrics in 5 families from copies of one fit. Each index.html is rendered in
headless Chromium (Debian's `chromium`):
  - the screenshot is not blank: enough pixels differ from the page background, and the
    plots' colours are there;
  - the DOM the browser built holds one data-plot="family" SVG per family and one
    data-plot="fabric" SVG per fabric (families and fabrics read from report.json);
  - every <svg> of the page is well-formed XML.

  check_report_in_browser.py --yarnfit BIN --work DIR [--keep DIR]

--keep copies the screenshots there (to look at them). Exit 0 pass, 1 fail, 77 skipped
(no chromium and not under CI=true).
"""
import argparse
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)




def chromium():
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    return None


def browser(binary, *args):
    # As root Chromium needs --no-sandbox; --disable-gpu and no crash reporter keep it quiet.
    cmd = [binary, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           "--disable-dev-shm-usage", "--no-first-run", *args]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        fail(f"{' '.join(cmd)} exited {r.returncode}\n{r.stderr[-2000:]}")
    return r.stdout


def png_pixels(path):
    """(width, height, rows of RGB tuples) of an 8-bit RGB or RGBA PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{path}: not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                fail(f"{path}: PNG depth {depth} colour type {colour} interlace {interlace} not handled")
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(height):
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, rows, bpp


def check_screenshot(path):
    width, height, rows, bpp = png_pixels(path)
    background = rows[0][0:3]
    differ, colours = 0, set()
    for y in range(0, height, 2):
        row = rows[y]
        for x in range(0, width * bpp, 2 * bpp):
            px = row[x:x + 3]
            if px != background:
                differ += 1
                r, g, b = px
                if max(r, g, b) - min(r, g, b) > 60:  # a saturated colour: a plot's mark or line
                    colours.add((r // 32, g // 32, b // 32))
    sampled = (height // 2) * (width // 2)
    share = differ / max(sampled, 1)
    print(f"{path}: {width}x{height}, {100 * share:.1f} % of pixels not background, {len(colours)} colour bins")
    if share < 0.03:
        fail(f"{path}: the screenshot is blank ({100 * share:.2f} % of pixels differ from the background)")
    if len(colours) < 4:
        fail(f"{path}: no plot colours on the screenshot ({len(colours)} saturated colour bins)")


def check_page(binary, report_dir, shot, keep):
    index = os.path.join(report_dir, "index.html")
    html = open(index, encoding="utf-8").read()
    svgs = re.findall(r"<svg\b.*?</svg>", html, flags=re.S)
    if not svgs:
        fail(f"{index}: no <svg>")
    for k, s in enumerate(svgs):
        try:
            ET.fromstring(s)
        except ET.ParseError as e:
            fail(f"{index}: SVG {k} is not well-formed XML: {e}\n{s[:300]}")
    print(f"{index}: {len(svgs)} SVGs, all well-formed XML")

    report = json.load(open(os.path.join(report_dir, "report.json")))
    dom = browser(binary, "--dump-dom", "file://" + os.path.abspath(index))
    plots = re.findall(r"<svg\b[^>]*>", dom)
    if len(plots) != len(svgs):
        fail(f"the browser's DOM has {len(plots)} <svg> elements, the page {len(svgs)}")
    for fam in report["families"]:
        name = fam["family"]
        n = sum(1 for p in plots if 'data-plot="family"' in p and f'data-family="{name}"' in p)
        if n != 1:
            fail(f"family {name!r}: {n} family plots in the DOM (expected 1)")
    for fab in report["fabrics"]:
        n = sum(1 for p in plots if 'data-plot="fabric"' in p and f'data-fabric="{fab["id"]}"' in p)
        if n != 1:
            fail(f"fabric {fab['id']!r}: {n} fabric plots in the DOM (expected 1)")
    print(f"DOM: one plot per family ({len(report['families'])}) and per fabric ({len(report['fabrics'])})")

    browser(binary, f"--screenshot={shot}", "--window-size=1280,2600", "file://" + os.path.abspath(index))
    check_screenshot(shot)
    if keep:
        os.makedirs(keep, exist_ok=True)
        shutil.copy(shot, keep)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--yarnfit", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--keep")
    a = ap.parse_args()
    binary = chromium()
    if not binary:
        if os.environ.get("CI") == "true":
            fail("chromium is not installed (scripts/install_deps.sh installs it)")
        print("SKIP: chromium is not installed")
        sys.exit(77)
    work = a.work
    shutil.rmtree(work, ignore_errors=True)
    db = os.path.join(work, "db")
    os.makedirs(db)

    def yarnfit(*args, codes=(0,)):
        r = subprocess.run([a.yarnfit, *args], capture_output=True, text=True)
        if r.returncode not in codes:
            fail(f"yarnfit {' '.join(args)} exited {r.returncode}\n{r.stderr}")
        return r

    bending = ["--ktheta-weft", "2e-6", "--ktheta-bias", "2.6e-6", "--ktheta-warp", "3.4e-6", "--bending", "weft"]
    for fid, family, extra in [("jersey_a", "jersey", bending), ("jersey_b", "jersey", ["--kxx", "90"]),
                               ("rib_c", "rib", ["--kyy", "150", "--bias", "0"])]:
        yarnfit("synth", "shell", "--out", os.path.join(db, fid), "--id", fid, "--family", family, "--points", "5",
                *extra)
    out = os.path.join(work, "batch")
    yarnfit("batch", db, "--out", out, "--stages", "shell", "--quiet")
    check_page(binary, os.path.join(out, "report"), os.path.join(work, "report_small.png"), a.keep)

    # 30 fabrics in 5 families: copies of one fit under other ids and families.
    many = os.path.join(work, "many")
    shell = json.load(open(os.path.join(out, "fabrics", "jersey_a", "shell_fit.json")))
    for k in range(30):
        fid = f"knit_{k:02d}_with_a_longer_name"
        shell["fabric"], shell["family"] = fid, f"family_{k % 5}"
        shell["errors"]["stretch_force_pct"] = 0.6 * k
        os.makedirs(os.path.join(many, fid))
        json.dump(shell, open(os.path.join(many, fid, "shell_fit.json"), "w"))
    yarnfit("report", many, "--out", os.path.join(work, "many_report"), "--quiet")
    check_page(binary, os.path.join(work, "many_report"), os.path.join(work, "report_30.png"), a.keep)
    print("PASS")


if __name__ == "__main__":
    main()
