#!/usr/bin/python3
"""An optical set that changes specular reflectance or transmittance equals the case whose
materials have those values.

usage: check_optical_set_specular.py RADNET SOURCE_DIR WORK_DIR

The OSR radiator example (cases/examples/osr-radiator.yaml) is run three ways: as shipped;
with an end-of-life optical set `eol` (the OSR's α 0.08 → 0.15 and its solar ρs 0.90 → 0.70,
the cover glass's solar τ 0.90 → 0.80) and two design cases, `bol` (base) and `eol`; and with
the materials themselves at the end-of-life values. The set gets networks of its own, traced
with its optics from the same diffuse F with the same seeds, and sunlight through its mirror
and window is traced with its ρs and τ: its loads, solar exitance, temperatures and GR must
equal the third run's, and the `bol` case the shipped run's. Both sides solve these
11-node networks by dense LU, so they agree to rounding: tolerance 1e-9 of each quantity's
largest magnitude. The `eol` case must also differ from `bol` (the set is not ignored).
"""
import os
import subprocess
import sys

import h5py
import numpy as np

RADNET, SOURCE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
RELATIVE = 1e-9
failures = []
os.makedirs(WORK, exist_ok=True)

shipped = open(os.path.join(SOURCE, "cases/examples/osr-radiator.yaml")).read()
OSR = "osr: {emissivity: 0.80, absorptivity: 0.08, specular_reflectance: 0.19, solar_specular_reflectance: 0.90}"
GLASS = "cover_glass: {emissivity: 0.84, absorptivity: 0.05, transmittance: 0.0, solar_transmittance: 0.90}"
assert OSR in shipped and GLASS in shipped, "the example's materials changed: update this test"
with_set = shipped.replace(
    "solver:\n",
    "optics:\n  eol: {osr: {absorptivity: 0.15, solar_specular_reflectance: 0.70},"
    " cover_glass: {solar_transmittance: 0.80}}\ncases:\n  bol: {}\n  eol: {optics: eol}\nsolver:\n", 1)
eol_materials = shipped.replace(OSR, OSR.replace("absorptivity: 0.08", "absorptivity: 0.15")
                                .replace("solar_specular_reflectance: 0.90", "solar_specular_reflectance: 0.70")) \
                       .replace(GLASS, GLASS.replace("solar_transmittance: 0.90", "solar_transmittance: 0.80"))

results = {}
for name, text in [("shipped", shipped), ("with_set", with_set), ("eol_materials", eol_materials)]:
    path = os.path.join(WORK, name + ".yaml")
    with open(path, "w") as f:
        f.write(text)
    r = subprocess.run([RADNET, "run", path, "-o", name + ".h5"], cwd=WORK, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"radnet run {name}: exit {r.returncode}: {r.stderr[-800:]}")
    results[name] = h5py.File(os.path.join(WORK, name + ".h5"), "r")

a, plain, eol = results["with_set"], results["shipped"], results["eol_materials"]
P = plain["loads/solar"].shape[0]
if list(a["cases/position_start"][()]) != [0, P, 2 * P]:
    failures.append(f"/cases/position_start {a['cases/position_start'][()]}, expected [0, {P}, {2 * P}]")


def compare(label, got, want):
    scale = max(np.abs(want).max(), 1e-300)
    worst = np.abs(got - want).max()
    if not worst <= RELATIVE * scale:
        failures.append(f"{label}: differs by {worst:.3e} (largest magnitude {scale:.3e})")


for key in ["loads/solar", "loads/albedo", "loads/earth_ir", "loads/incident_solar", "solution/exitance_solar",
            "solution/temperature"]:
    both = a[key][()]
    compare(key + " (bol against the shipped run)", both[:P], plain[key][()])
    compare(key + " (eol against the end-of-life materials)", both[P:], eol[key][()])
compare("GR of the set eol", a["optics/eol/radiative_exchange"][()], eol["network/radiative_exchange"][()])
compare("GR to space of the set eol", a["optics/eol/gr_space"][()], eol["network/gr_space"][()])
for key in ["emissivity", "absorptivity", "specular_reflectance", "solar_specular_reflectance", "transmittance",
            "solar_transmittance"]:
    compare(f"/optics/eol/{key}", a["optics/eol/" + key][()], eol["optics/base/" + key][()])
# The set's G̃ is its own: one decomposition for the case's optics, one for the set's.
if int(a["report"].attrs["eigendecompositions"]) != 2:
    failures.append(f"/report eigendecompositions {a['report'].attrs['eigendecompositions']}, expected 2")
if np.abs(a["loads/solar"][P:] - a["loads/solar"][:P]).max() < 1.0:
    failures.append("the eol case's solar loads equal the bol case's: the set's optics were not used")

for line in failures:
    print("FAIL", line)
print("optical set with its own ρs, τ:", "failed" if failures else "equals the materials' run")
sys.exit(1 if failures else 0)
