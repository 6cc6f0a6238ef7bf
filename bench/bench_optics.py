#!/usr/bin/python3
"""Optics against temperature at scale: the same model with a radiator of constant ε and
with an ε(T) table (0.35 at 150 K to 0.80 at 350 K), steady states at every
position, in one session on one machine. Reports the thermal stage's time for both, the
GRs formed (each a rank-|U| update, U the radiator's nodes) and the eigendecompositions
(1 in both). Writes a Markdown table.

usage: bench_optics.py RADNET OUT.md CASE.yaml RADIATOR_GEOMETRY_NAME
"""
import os
import re
import subprocess
import sys
import tempfile

import h5py

# A ramp over every temperature the face reaches, so that ε moves at every position (a
# narrow VO₂ step would leave a cold face on its low branch and cost one GR).
VO2 = "  vo2: {absorptivity: 0.08, emissivity: {table: [[150.0, 0.35], [350.0, 0.80]]}}\n"
# Steady states: every node its own balance with a constant dissipation on the radiator's side.
THERMAL = "thermal:\n  space_temperature: 3.0\n"


def variant(path, radiator, table):
    text = open(path).read()
    text = text.replace("materials:\n", "materials:\n" + VO2, 1)
    material = "vo2" if table else "osr"
    text = re.sub(r"(name: %s,[^\n]*front: )\w+" % re.escape(radiator), r"\g<1>" + material, text)
    return text + THERMAL


def run(radnet, case, radiator, table):
    folder = os.path.dirname(os.path.abspath(case))
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", dir=folder, delete=False) as f:
        f.write(variant(case, radiator, table))
        yaml = f.name
    out = tempfile.mktemp(suffix=".h5")
    try:
        proc = subprocess.run([radnet, "run", yaml, "-o", out], capture_output=True, text=True)
    finally:
        os.unlink(yaml)
    if proc.returncode != 0:
        raise SystemExit(f"{case}: radnet exited {proc.returncode}\n{proc.stderr[-2000:]}")
    with h5py.File(out, "r") as h5:
        report = dict(h5["/report"].attrs)
        n = h5["/nodes/name"].shape[0]
        temperature = h5["/solution/temperature"][:]
    os.unlink(out)
    return n, report, temperature


def main():
    radnet, out_md, case, radiator = sys.argv[1:5]
    n, base, t_base = run(radnet, case, radiator, False)
    _, vo2, t_vo2 = run(radnet, case, radiator, True)
    rows = [("constant ε (OSR, 0.80)", base, "–"), ("ε(T) table, 0.35–0.80 over 150–350 K", vo2, str(vo2.get("exchange_updates", 0)))]
    with open(out_md, "w") as f:
        f.write(f"Model: {os.path.basename(case)} ({n} nodes), radiator `{radiator}`; steady state at every position.\n\n")
        f.write("| radiator | thermal stage (s) | GRs formed | eigendecompositions | whole run (s) |\n|---|---|---|---|---|\n")
        for label, r, grs in rows:
            total = sum(v for k, v in r.items() if k.startswith("time_") and k.endswith("_s"))
            f.write(f"| {label} | {r['time_thermal_s']:.2f} | {grs} | {r.get('eigendecompositions', 1)} | {total:.2f} |\n")
        ratio = vo2["time_thermal_s"] / base["time_thermal_s"]
        f.write(f"\nThermal stage ratio table / constant: {ratio:.2f}; largest temperature difference "
                f"{abs(t_vo2 - t_base).max():.2f} K .\n")
    print(open(out_md).read())


main()
