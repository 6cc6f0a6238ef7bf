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
The thermostat's set points and power must be those of the case. The whole ESATAN deck (nodes,
GL, GR, capacitances, arrays, the thermostat as logic) integrated here by backward Euler at
0.5 s reproduces radnet's transient at a 1 s step within 0.05 K (measured 0.02 K: both
integrators' step errors; at radnet's default 10 s step its own step error is 0.12 K on the
90 J/K end faces). With two design cases and no --case, one deck per case is written.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

from network_step import backward_euler_step

RADNET, SOURCE, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
TOLERANCE_W = 1e-9
TRANSIENT_K = 0.05
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


def integrate_esatan(text, h5):
    """Backward Euler over the deck's one period at 0.5 s steps, its loads from its arrays and its
    thermostat logic evaluated at the start of each step, as a deck user's solver would."""
    absolute = float(re.search(rf"TABS = ({NUMBER});", text).group(1))
    period = float(re.search(rf"PERIOD = ({NUMBER});", text).group(1))
    nodes = {}
    for kind, number, rest in re.findall(r"^\s*([DXB])(\d+) = '[^']*'(.*);$", text, re.M):
        fields = {k.strip(): float(v) for k, v in re.findall(rf"(\w+) = ({NUMBER})", rest)}
        nodes[int(number)] = (kind, fields)
    numbers = sorted(nodes)
    index = {n: k for k, n in enumerate(numbers)}
    t = np.array([nodes[n][1]["T"] + absolute for n in numbers])
    c = np.array([nodes[n][1].get("C", 0.0) for n in numbers])
    fixed = np.array([nodes[n][0] == "B" for n in numbers])
    base = {k: np.array([nodes[n][1].get(k, 0.0) for n in numbers]) for k in ("QS", "QA", "QE", "QI")}
    pairs = {kind: [(index[int(a)], index[int(b)], float(v)) for a, b, v in
                    re.findall(rf"^\s*{kind}\((\d+), (\d+)\) = ({NUMBER});", text, re.M)] for kind in ("GL", "GR")}
    sigma = float(re.search(rf"STEFAN = ({NUMBER});", text).group(1))
    arrays = esatan_arrays(text)
    heater = re.search(r"HTP1 = (\S+);.*HTON1 = (\S+);.*HTOFF1 = (\S+);.*HTR1 = (\d)", text, re.S)
    sensor = index[int(re.search(r"IF \(T(\d+) < HTON1\)", text).group(1))]
    heated = index[int(re.search(r"^\s*QI(\d+) = .*HTR1", text, re.M).group(1))]
    power, on_c, off_c, state = float(heater.group(1)), float(heater.group(2)), float(heater.group(3)), int(heater.group(4))
    n = len(t)
    gl = np.zeros((n, n)); gr = np.zeros((n, n))
    for i, j, g in pairs["GL"]:
        gl[i, j] += g; gl[j, i] += g
    for i, j, g in pairs["GR"]:
        gr[i, j] += g; gr[j, i] += g

    def loads(time):
        q = sum(base.values()).copy()
        for (kind, node), a in arrays.items():
            i = index[node]
            q[i] += np.interp(time, a[:, 0], a[:, 1]) - base[kind][i]
        return q

    with h5py.File(h5) as f:
        times = f["/orbit/time"][:]
    dt, now, out, p = 0.5, 0.0, [t.copy()], 1
    while p < len(times):
        step = min(dt, times[p] - now)
        if t[sensor] - absolute < on_c:
            state = 1
        elif t[sensor] - absolute > off_c:
            state = 0
        q = loads(now + step)
        q[heated] += state * power
        t, now = backward_euler_step(t, t, q, gl, gr, c, sigma, fixed, step), now + step
        if abs(now - times[p]) < 1e-9:
            out.append(t.copy())
            p += 1
    return np.array(out)


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
    # The whole deck (nodes, GL, GR, arrays, thermostat logic) integrated here against radnet's
    # transient at a 1 s step (at its default 10 s, radnet's own step error is 0.12 K here).
    fine = open(case).read().replace("time_step: 10.0", "time_step: 1.0")
    open(os.path.join(WORK, "fine.yaml"), "w").write(fine)
    run("run", "fine.yaml", "-o", "fine.h5", "-q")
    run("export", "fine.h5", "--format", "esatan", "-o", "fine.d")
    deck_t = integrate_esatan(open(os.path.join(WORK, "fine.d")).read(), os.path.join(WORK, "fine.h5"))
    with h5py.File(os.path.join(WORK, "fine.h5")) as f:
        radnet_t = f["/solution/temperature"][:]
    err = np.abs(deck_t[:, :radnet_t.shape[1]] - radnet_t).max(axis=0)
    print("whole-orbit ESATAN deck integrated here (backward Euler, 0.5 s): largest |T_deck − T_radnet| per node, K:",
          np.round(err, 3))
    if not err.max() < TRANSIENT_K:
        failures.append(f"the deck's transient differs from radnet's by {err.max()} K (bound {TRANSIENT_K} K)")
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
