#!/usr/bin/python3
"""Specular radiators against diffuse ones on the same model (issue 33's measurement).

Runs bench/cases/satellite-osr-6402.yaml twice with the same settings: its RADIATOR material
once as OSRs with specular reflectance (ρs 0.19 IR, 0.90 solar) and once with the same ε, α
diffuse, and writes the stage times and their ratio to a Markdown file.

usage: bench/bench_specular.py build/radnet OUT.md [CASE.yaml]
"""
import os
import subprocess
import sys
import tempfile
import time

import h5py

VARIANTS = {
    "diffuse": "{emissivity: 0.80, absorptivity: 0.08}",
    "specular (OSR)": "{emissivity: 0.80, absorptivity: 0.08, specular_reflectance: 0.19, "
                      "solar_specular_reflectance: 0.90}",
}


# An end-of-life optical set that changes the OSR's solar ρs (a set with networks of its own),
# against a run whose material has those values.
EOL_MATERIAL = ("{emissivity: 0.80, absorptivity: 0.15, specular_reflectance: 0.19, "
                "solar_specular_reflectance: 0.70}")
EOL_SET = ("optics:\n  eol: {RADIATOR: {absorptivity: 0.15, solar_specular_reflectance: 0.70}}\n"
           "cases:\n  bol: {}\n  eol: {optics: eol}\n")


def run(radnet, case_path, material, folder, blocks=""):
    text = open(case_path).read()
    include_dir = os.path.dirname(os.path.abspath(case_path))
    text = text.replace("include: materials/", "include: " + include_dir + "/materials/")
    text = text.replace("  include:", "  RADIATOR: " + material + "\n  include:", 1)
    text = text.replace("solver:\n", blocks + "solver:\n", 1)
    path = os.path.join(folder, "case.yaml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(folder, "out.h5")
    t0 = time.monotonic()
    subprocess.run([radnet, "run", path, "-o", out], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    with h5py.File(out) as h5:
        r = h5["/report"].attrs
        stages = {k[5:-2]: float(r[k]) for k in r if k.startswith("time_") and k.endswith("_s")}
        return wall, stages, int(r["eigendecompositions"]), str(r.get("solar_band_method", ""))


def main():
    radnet, out_md = sys.argv[1], sys.argv[2]
    case = sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(__file__), "cases",
                                                               "satellite-osr-6402.yaml")
    rows = {}
    for name, material in VARIANTS.items():
        with tempfile.TemporaryDirectory() as folder:
            rows[name] = run(radnet, case, material, folder)
    with tempfile.TemporaryDirectory() as folder:
        rows["OSR, BOL + EOL set (2 cases)"] = run(radnet, case, VARIANTS["specular (OSR)"], folder, EOL_SET)
    with tempfile.TemporaryDirectory() as folder:
        rows["OSR with the EOL values"] = run(radnet, case, EOL_MATERIAL, folder)
    base = rows["diffuse"][0]
    with open(out_md, "w") as f:
        f.write("# Specular radiators against diffuse ones\n\n")
        f.write(f"Model: {os.path.basename(case)}; command: `bench/bench_specular.py {radnet} {out_md}`.\n")
        f.write(f"Machine: {os.cpu_count()} cores, {os.uname().sysname} {os.uname().release}.\n\n")
        f.write("| radiators | whole run, s | ratio | view factors, s | loads, s | band solves, s "
                "| eigendecompositions | solar band |\n|---|---|---|---|---|---|---|---|\n")
        for name, (wall, stages, eig, method) in rows.items():
            f.write(f"| {name} | {wall:.2f} | {wall / base:.2f} | {stages.get('view_factors', 0):.2f} | "
                    f"{stages.get('environment_loads', 0):.2f} | {stages.get('band_solves', 0):.3f} | {eig} | "
                    f"{method} |\n")
        f.write("\nBoth runs use the case's own settings (Monte Carlo view factors, 4,000 rays per node: the\n"
                "same work on both sides). The specular run traces the rows that see a radiator (IR and\n"
                "solar bands apart, since the OSR's ρs differs between them), follows the sunlight the\n"
                "radiators reflect (1,024 points per lit radiator node and position) and solves its solar\n"
                "band on its own network, refined with the one decomposition's core as preconditioner:\n"
                "`eigendecompositions` stays 1.\n\n"
                "The last two rows: an end-of-life optical set that changes the OSR's solar ρs (0.90 → 0.70)\n"
                "and α (0.08 → 0.15) gets its own traced network and its own eigendecomposition (2 in all);\n"
                "its case's loads equal those of the run whose material has the EOL values (bit for bit when\n"
                "compared on this model by hand; tests/check_optical_set_specular.py checks it on the example).\n"
                f"The two-case run against the two single runs it replaces: "
                f"{rows['OSR, BOL + EOL set (2 cases)'][0] / (rows['specular (OSR)'][0] + rows['OSR with the EOL values'][0]):.2f}.\n")
    print(open(out_md).read())


if __name__ == "__main__":
    main()
