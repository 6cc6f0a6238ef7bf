#!/usr/bin/python3
"""Whole-orbit decks: `radnet export` of a run with an orbit writes every position's loads.

usage: check_orbit_decks.py RADNET SOURCE_DIR WORK_DIR

For the 3U CubeSat example (a periodic transient with a thermostat) and the same case
without its thermal block (loads only), the ESATAN deck's arrays, interpolated linearly at
the run's position times as its $VARIABLES1 does (INTRP1 at T0 + MOD(t − T0, PERIOD)), must
equal /loads/solar, /loads/albedo and /loads/earth_ir (QS, QA, QE) and the dissipation
without the heater (QI: the thermostat is logic on its sensor) to 1e-9 W: the deck prints 12
significant digits of values of at most ~40 W. Loads that do not change stay node values,
which must equal every position's. The SINDA deck's arrays must hold the sum of the four.
The thermostat's set points and power must be those of the case. With two design cases and no
--case, one deck per case is written.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

RADNET, SOURCE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
TOLERANCE_W = 1e-9
NUMBER = r"[-+0-9.eE]+"
failures = []


def run(*args):
    r = subprocess.run([RADNET, *args], cwd=WORK, capture_output=True, text=True)
    if r.returncode != 0:
        failures.append(f"radnet {' '.join(args)}: exit {r.returncode}: {r.stderr[-500:]}")
    return r


def esatan_arrays(text):
    arrays = {}
    for kind, node, count, body in re.findall(r"^\s*(Q[SAEI])_(\d+)\(2, (\d+)\) =\s*(.*?);", text, re.M | re.S):
        v = np.array([float(x) for x in re.findall(NUMBER, body)]).reshape(-1, 2)
        if len(v) != int(count):
            failures.append(f"array {kind}_{node}: {len(v)} doublets, declared {count}")
        arrays[(kind, int(node))] = v
    return arrays


def node_values(text):
    nodes = {}
    for number, rest in re.findall(r"^\s*[DX](\d+) = '[^']*'(.*);$", text, re.M):
        nodes[int(number)] = {k.strip(): float(v) for k, v in re.findall(rf"(\w+) = ({NUMBER})", rest)}
    return nodes


def check_esatan(deck, h5, thermal):
    text = open(deck).read()
    period = float(re.search(rf"PERIOD = ({NUMBER});", text).group(1))
    arrays, nodes = esatan_arrays(text), node_values(text)
    with h5py.File(h5) as f:
        t = f["/orbit/time"][:]
        expected = {"QS": f["/loads/solar"][:], "QA": f["/loads/albedo"][:], "QE": f["/loads/earth_ir"][:]}
        n = len(f["/nodes/name"])
        if thermal:
            expected["QI"] = f["/solution/heat/dissipation"][:]
    worst, tabled = 0.0, 0
    for kind, values in expected.items():
        for i in range(values.shape[1]):
            if (kind, i + 1) in arrays:
                a = arrays[(kind, i + 1)]
                got = np.interp(t[0] + np.mod(t - t[0], period), a[:, 0], a[:, 1])
                tabled += 1
            else:
                got = np.full(len(t), nodes[i + 1][kind])
            worst = max(worst, np.abs(got - values[:, i]).max())
    print(f"{os.path.basename(deck)}: {tabled} arrays, largest |load_deck − load_radnet| = {worst:.2e} W over {len(t)} positions, {n} nodes")
    if not worst <= TOLERANCE_W:
        failures.append(f"{deck}: loads differ by {worst} W")
    if tabled == 0:
        failures.append(f"{deck}: no load array")
    return text


def check_sinda(deck, h5):
    text = open(deck).read()
    period = float(re.search(rf"PERIOD = ({NUMBER})", text).group(1))
    arrays = {int(a) - 1000: np.array([float(x) for x in re.findall(NUMBER, body)]).reshape(-1, 2)
              for a, body in re.findall(r"^\s*(\d+) =\n(.*?)(?=^\s*\d+ =|^HEADER)", text, re.M | re.S)}
    with h5py.File(h5) as f:
        t = f["/orbit/time"][:]
        total = f["/loads/solar"][:] + f["/loads/albedo"][:] + f["/loads/earth_ir"][:]
        total = np.pad(total, ((0, 0), (0, len(f["/nodes/name"]) - total.shape[1])))
        total += f["/solution/heat/dissipation"][:]
    worst = 0.0
    for node, a in arrays.items():
        got = np.interp(t[0] + np.mod(t - t[0], period), a[:, 0], a[:, 1])
        worst = max(worst, np.abs(got - total[:, node - 1]).max())
    print(f"{os.path.basename(deck)}: {len(arrays)} arrays, largest |Q_deck − Q_radnet| = {worst:.2e} W")
    if not arrays or not worst <= TOLERANCE_W:
        failures.append(f"{deck}: {len(arrays)} arrays, sources differ by {worst} W")


def main():
    os.makedirs(WORK, exist_ok=True)
    case = os.path.join(SOURCE, "cases", "examples", "cubesat-3u.yaml")
    run("run", case, "-o", "cube.h5", "-q")
    run("export", "cube.h5", "--format", "esatan", "-o", "cube.d")
    text = check_esatan(os.path.join(WORK, "cube.d"), os.path.join(WORK, "cube.h5"), True)
    for needle in ("HTP1 = 3;", "HTON1 = 0;", "HTOFF1 = 5;", "IF (T13 < HTON1) THEN", "QI13 = ", "CALL SLCRNC"):
        if needle not in text:
            failures.append(f"cube.d lacks '{needle}'")
    run("export", "cube.h5", "--format", "sinda", "-o", "cube.sin")
    check_sinda(os.path.join(WORK, "cube.sin"), os.path.join(WORK, "cube.h5"))
    # Loads only: the same geometry and orbit without a thermal block.
    source = open(case).read()
    source = source[:source.index("\nthermal:")] + "\n"
    source = source.replace(",\n                shell: {material: al6061, thickness: 0.0015}", "")
    open(os.path.join(WORK, "loads.yaml"), "w").write(source)
    run("run", "loads.yaml", "-o", "loads.h5", "-q")
    run("export", "loads.h5", "--format", "esatan", "-o", "loads.d")
    text = check_esatan(os.path.join(WORK, "loads.d"), os.path.join(WORK, "loads.h5"), False)
    if "NO TEMPERATURES" not in text or re.search(r"^\s*D\d+ = '[^']*', T =", text, re.M):
        failures.append("loads-only deck: a temperature made up, or no word that none exist")
    # Two design cases, no --case: one deck each.
    hot_cold = os.path.join(SOURCE, "cases", "examples", "cubesat-hot-cold.yaml")
    text = open(hot_cold).read().replace("positions: 72", "positions: 12").replace("rays: 50000", "rays: 5000")
    text = re.sub(r"^uncertainty:.*$", "", text, flags=re.M)
    open(os.path.join(WORK, "hc.yaml"), "w").write(text)
    run("run", "hc.yaml", "-o", "hc.h5", "-q")
    r = run("export", "hc.h5", "--format", "esatan", "-o", "hc.d")
    for name in ("hc-hot.d", "hc-cold.d"):
        if not os.path.exists(os.path.join(WORK, name)):
            failures.append(f"no {name} (stderr: {r.stderr})")


main()
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
