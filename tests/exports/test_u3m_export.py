#!/usr/bin/env python3
"""U3M exports against the U3M 1.1 schemas kept in exports/u3m_schemas (issue 36).

Exports the kept fits of tests/exports/data (the bundled example's, with its record; the
acrylic 1x1 rib's stiffening-law fit, without one) as folders and as .u3ma files, validates
every material and physics file with python3-jsonschema (Draft 7 and its format checker, plus
RFC 3339 for the dates, which that checker leaves out without rfc3339-validator), and checks
that the physics file's yarnfit block holds the fitted values and that the .u3ma is a plain
zip of the two files with nothing after it.

Usage: test_u3m_export.py YARNFIT SOURCE_DIR
Exit 77 (ctest: skipped) when python3-jsonschema is missing, unless CI=true.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile

SKIP = 77
try:
    import jsonschema
except ImportError:
    if os.environ.get("CI") == "true":
        print("FAIL: python3-jsonschema is missing, and CI=true (scripts/install_deps.sh installs it)")
        sys.exit(1)
    print("SKIP: python3-jsonschema is missing (apt-get install python3-jsonschema)")
    sys.exit(SKIP)

yarnfit, source = sys.argv[1], sys.argv[2]
schemas = os.path.join(source, "exports", "u3m_schemas")
data = os.path.join(source, "tests", "exports", "data")
material_schema = json.load(open(os.path.join(schemas, "u3m_schema.json")))
physics_schema = json.load(open(os.path.join(schemas, "physics_schema.json")))
checker = jsonschema.Draft7Validator.FORMAT_CHECKER
RFC3339 = re.compile(r"^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?(Z|[+-]\d{2}:\d{2})$")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def schema_errors(doc, schema):
    return [e.message for e in jsonschema.Draft7Validator(schema, format_checker=checker).iter_errors(doc)]


def export(fit, out, *extra):
    r = subprocess.run([yarnfit, "export", fit, "--format", "u3m", "--out", out, *extra], capture_output=True, text=True)
    return r


def validate(name, material, physics, fit_dir, with_record, with_yarn):
    errors = schema_errors(material, material_schema)
    check(not errors, f"{name}: the material file is valid U3M 1.1 {errors[:3]}")
    errors = schema_errors(physics, physics_schema)
    check(not errors, f"{name}: the physics file is valid U3M 1.1 physics {errors[:3]}")
    m = material["material"]
    check(RFC3339.match(m["created"]) and RFC3339.match(m["modified"]), f"{name}: created and modified are RFC 3339")
    p = m["physics"]
    check(p["devices"]["fab"] == "physics/physics.json", f"{name}: devices.fab points at the physics file")
    check(p["material_type"] == {"type": "Knit", "name": None}, f"{name}: material_type Knit")
    block = physics["custom"]["yarnfit"]
    shell = json.load(open(os.path.join(fit_dir, "shell_fit.json")))
    fitted = {k: v for k, v in shell["params"].items() if v is not None}
    exported = {k: v["value"] for k, v in block["shell_law"]["fitted"].items()}
    check(exported == fitted, f"{name}: the shell law's parameters are the fit's, bit for bit")
    check(all(v["unit"] for v in block["shell_law"]["fitted"].values()), f"{name}: every shell parameter has a unit")
    check(set(block["shell_law"]["errors_pct"]) == {d["direction"] for d in shell["directions"]},
          f"{name}: errors for every tested direction")
    check(physics["raw_data"] is None, f"{name}: raw_data is null (no FAB measurement)")
    if with_yarn:
        yarn = json.load(open(os.path.join(fit_dir, "yarn_fit.json")))
        check({k: v["value"] for k, v in block["yarn"]["fitted"].items()} == yarn["params"],
              f"{name}: the yarn parameters are the fit's")
    else:
        check(block["yarn"] is None, f"{name}: no yarn block without the yarn stage")
    if with_record:
        check(p["weight"] == 180.0, f"{name}: weight 180 g/m2 from the record")
        check(p["construction"] == {"type": "Single jersey", "name": None}, f"{name}: construction Single jersey")
        check(p["composition"]["parts"] == [{"ratio": 1.0, "type": "Polyester", "name": None}],
              f"{name}: composition from the yarns")
        check(re.fullmatch(r"[0-9a-f]{64}", block["provenance"]["record_sha256"] or "") is not None,
              f"{name}: the record's fingerprint")
    else:
        check(p["weight"] is None and p["composition"] is None and p["construction"] is None,
              f"{name}: without the record, weight, composition and construction are null")


with tempfile.TemporaryDirectory() as tmp:
    cases = [("stockinette_demo", True, True), ("acrylic_rib", False, False)]
    for name, with_record, with_yarn in cases:
        fit = os.path.join(tmp, name)
        os.makedirs(fit)
        shutil.copy(os.path.join(data, name + "_shell_fit.json"), os.path.join(fit, "shell_fit.json"))
        if with_yarn:
            shutil.copy(os.path.join(data, name + "_yarn_fit.json"), os.path.join(fit, "yarn_fit.json"))
        extra = ["--record", os.path.join(source, "examples", "fabrics", name)] if with_record else []

        folder = os.path.join(tmp, name + "_u3m")
        r = export(fit, folder, *extra)
        check(r.returncode == 0, f"{name}: export to a folder ({r.stderr.strip()})")
        material = json.load(open(os.path.join(folder, name + ".u3m")))
        physics = json.load(open(os.path.join(folder, "physics", "physics.json")))
        validate(name + " (folder)", material, physics, fit, with_record, with_yarn)

        archive = os.path.join(tmp, name + ".u3ma")
        r = export(fit, archive, *extra)
        check(r.returncode == 0, f"{name}: export to a .u3ma ({r.stderr.strip()})")
        raw = open(archive, "rb").read()
        check(raw[-22:-18] == b"PK\x05\x06", f"{name}: the .u3ma ends with its end-of-central-directory record")
        with zipfile.ZipFile(archive) as z:
            check(sorted(z.namelist()) == sorted([name + ".u3m", "physics/physics.json"]), f"{name}: the .u3ma holds the two files")
            check(all(i.compress_type in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED) for i in z.infolist()),
                  f"{name}: entries stored or deflated")
            validate(name + " (.u3ma)", json.loads(z.read(name + ".u3m")), json.loads(z.read("physics/physics.json")),
                     fit, with_record, with_yarn)

    # The validator does refuse: a material without its physics' devices, a physics file with a
    # key the schema does not know.
    broken = json.loads(json.dumps(material))
    del broken["material"]["physics"]["devices"]
    check(bool(schema_errors(broken, material_schema)), "the schema refuses a material without devices")
    check(bool(schema_errors({"schema": "1.1", "raw_data": None, "custom": None, "extra": 1}, physics_schema)),
          "the schema refuses an unknown key in the physics file")
    # What cannot be exported says why, exit 2, nothing written.
    os.makedirs(os.path.join(tmp, "empty"))
    r = export(os.path.join(tmp, "empty"), os.path.join(tmp, "never.u3ma"))
    check(r.returncode == 2 and "not the folder of a fit" in r.stderr and not os.path.exists(os.path.join(tmp, "never.u3ma")),
          "a folder without a fit: exit 2 with the reason, nothing written")

    # Issue 51's round trip: a FAB measurement imported, its shell law fitted, exported with
    # its record: the physics file carries the measurement's raw_data unchanged (and the
    # vendor's custom block) beside the fitted model, is valid U3M 1.1 physics, and imports again.
    fab_in = os.path.join(source, "tests", "data", "fab", "cupro_physics.json")
    record, fit = os.path.join(tmp, "cupro"), os.path.join(tmp, "cupro_fit")
    r = subprocess.run([yarnfit, "db", "import-fab", fab_in, "--out", record, "--denier", "75", "-q"], capture_output=True, text=True)
    check(r.returncode == 0, f"cupro: import ({r.stderr.strip()})")
    r = subprocess.run([yarnfit, "shell", "fit", record, "--out", fit, "--quiet"], capture_output=True, text=True)
    check(r.returncode == 0, f"cupro: shell fit ({r.stderr.strip()[-200:]})")
    archive = os.path.join(tmp, "cupro.u3ma")
    r = export(fit, archive, "--record", record)
    check(r.returncode == 0, f"cupro: export with the record ({r.stderr.strip()})")
    source_physics = json.load(open(fab_in))
    with zipfile.ZipFile(archive) as z:
        physics = json.loads(z.read("physics/physics.json"))
    errors = schema_errors(physics, physics_schema)
    check(not errors, f"cupro: the physics file with its measurement is valid U3M 1.1 physics {errors[:3]}")
    check(physics["raw_data"] == source_physics["raw_data"], "cupro: raw_data comes out as it went in")
    check(physics["custom"]["browzwear"] == source_physics["custom"]["browzwear"], "cupro: the vendor's custom block kept")
    check("shell_law" in physics["custom"]["yarnfit"], "cupro: the fitted model beside it")
    again = os.path.join(tmp, "cupro_again")
    r = subprocess.run([yarnfit, "db", "import-fab", archive, "--out", again, "--denier", "75", "-q"], capture_output=True, text=True)
    check(r.returncode == 0, f"cupro: the exported .u3ma imports again ({r.stderr.strip()})")
    same = r.returncode == 0 and all(
        open(os.path.join(record, "fab", f)).read() == open(os.path.join(again, "fab", f)).read()
        for f in os.listdir(os.path.join(record, "fab")) if f.endswith(".csv"))
    check(same, "cupro: every test's samples the same after the round trip")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
