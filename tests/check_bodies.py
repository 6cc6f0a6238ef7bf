#!/usr/bin/python3
"""Orbits about other bodies and optics against temperature, end to end (issue 35).

usage: check_bodies.py RADNET SOURCE_DIR WORK_DIR

Runs the lunar and Mars orbiter examples (hot and cold design cases each) and checks what
their files say against closed forms and the models' own definitions:
- /orbit says which body; the sweep spans the nodal period, within 1e-3 of 2π √(a³/μ) (the
  J2 corrections about the Moon and Mars at these heights are below 1e-3);
- the Mars cases' solar flux is 1361 / r² at perihelion and aphelion (1.381 and 1.666 au,
  a (1 ∓ e) of Standish's elements) within 0.5 %;
- the Moon's IR on the nadir face: above 900 W/m² over the subsolar point, at night the
  night floor σ 95⁴ times the face's view factor to the Moon (to 1 %);
- one eigendecomposition for both cases, GRs formed again as the VO₂ radiator's ε moves;
  the radiator's ε stays within its table and is higher in the hot case;
- the heat flows, with each node's loads at its own ε(T), balance to 1e-3 of the largest term.
"""
import math
import os
import subprocess
import sys

import h5py
import numpy as np

RADNET, SOURCE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
SIGMA = 5.670374419e-8
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def run(example):
    out = os.path.join(WORK, example + ".h5")
    r = subprocess.run([RADNET, "run", os.path.join(SOURCE, "cases/examples", example + ".yaml"), "-o", out],
                       cwd=WORK, capture_output=True, text=True)
    if r.returncode != 0:
        failures.append(f"{example}: exit {r.returncode}: {r.stderr[-800:]}")
        return None
    return h5py.File(out, "r")


def names(f):
    return [n.decode() for n in f["/nodes/name"][:]]


def case_ranges(f):
    start = f["/cases/position_start"][:]
    return [(int(start[k]), int(start[k + 1])) for k in range(len(start) - 1)]


def check_period(f, gm, radius, altitude, label):
    t = f["/orbit/time"][:]
    start = f["/cases/position_start"][:]
    period = 2 * math.pi * math.sqrt((radius + altitude) ** 3 / gm)
    times = t[start[0]:start[1]]
    # 36 regular positions from 0 to 35/36 of the nodal period, eclipse events between them
    # (one may fall after the last regular position, before the period ends).
    check(times.min() == 0.0 and times.max() >= period * 35 / 36 * (1 - 2e-3) and times.max() < period * (1 + 2e-3),
          f"{label}: sweep from {times.min()} to {times.max()} s, period {period} s")


def check_heat_balance(f, label):
    rel = f["/report"].attrs["heat_balance_max_relative_imbalance"]
    check(rel < 1e-3, f"{label}: heat flows balance to {rel} of the largest term")


def lunar():
    f = run("lunar-orbiter")
    if f is None:
        return
    check(f["/orbit"].attrs["body"] == "moon", "lunar: /orbit body")
    check_period(f, 4.9028000661e12, 1737.4e3, 100e3, "lunar")
    n = names(f)
    nadir = n.index("bus.+z")
    ir = f["/loads/incident_earth_ir"][:, nadir]
    vf = f["/loads/earth_view_factor"][:, nadir]
    hot = case_ranges(f)[0]
    check(ir[hot[0]:hot[1]].max() > 900.0, f"lunar: subsolar IR {ir[hot[0]:hot[1]].max()} W/m² (expected > 900)")
    night = f["/orbit/sunlit_fraction"][:] == 0
    floor = SIGMA * 95.0 ** 4 * vf[night]
    check(np.allclose(ir[night], floor, rtol=0.01), f"lunar: night IR {ir[night][:3]} vs σ 95⁴ F {floor[:3]}")
    check(f["/report"].attrs["eigendecompositions"] == 1, "lunar: one eigendecomposition")
    check(f["/report"].attrs["exchange_updates"] > 0, "lunar: GRs formed for ε(T)")
    rad = n.index("radiator")
    eps = f["/solution/emissivity"][:, rad]
    check(eps.min() >= 0.35 - 1e-12 and eps.max() <= 0.80 + 1e-12, f"lunar: radiator ε {eps.min()}..{eps.max()}")
    (h0, h1), (c0, c1) = case_ranges(f)
    check(eps[h0:h1].mean() > eps[c0:c1].mean(), f"lunar: hot ε {eps[h0:h1].mean()} ≤ cold {eps[c0:c1].mean()}")
    check_heat_balance(f, "lunar")


def mars():
    f = run("mars-orbiter")
    if f is None:
        return
    check(f["/orbit"].attrs["body"] == "mars", "mars: /orbit body")
    check_period(f, 4.282837362e13, 3396.19e3, 300e3, "mars")
    flux = f["/orbit/solar_flux"][:]
    (h0, _), (c0, _) = case_ranges(f)
    check(abs(flux[h0] / (1361.0 / 1.3814 ** 2) - 1) < 5e-3, f"mars: perihelion flux {flux[h0]}")
    check(abs(flux[c0] / (1361.0 / 1.6660 ** 2) - 1) < 5e-3, f"mars: aphelion flux {flux[c0]}")
    check(abs(f["/orbit/inclination"][0] - 92.65) < 0.1, f"mars: sun-synchronous inclination {f['/orbit/inclination'][0]}")
    check_heat_balance(f, "mars")


os.makedirs(WORK, exist_ok=True)
lunar()
mars()
for failure in failures:
    print("FAIL", failure)
print("bodies:", "all checks passed" if not failures else f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
