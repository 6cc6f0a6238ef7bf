#!/usr/bin/python3
"""Round trip of `radnet export`: the exported decks reproduce radnet's steady temperatures.

usage: check_export.py RADNET SOURCE_DIR WORK_DIR

For two steady runs (the network case cases/analytic/lumped-nodes.yaml: conductors, a user
GR, MLI, arithmetic nodes; and the hot/cold CubeSat made steady per position: surfaces,
shells, lumped nodes, a thermostat heater, two optical sets) each of the three formats
(ESATAN TMD deck, SINDA/FLUINT deck, CSV) is exported, parsed here with its own reader, and
solved here for its steady state by an independent damped Newton iteration on

    Q_i + Σ_j GL_ij (T_j − T_i) + σ Σ_j GR_ij (T_j⁴ − T_i⁴) = 0   (free nodes; boundary and space held)

started from 250 K everywhere (not from the deck's temperatures). Each solution must equal
/solution/temperature at the exported position to 2e-6 K: radnet's Newton stops at 1e-9 of
each node's largest flow (about 1e-7 K here) and the decks print 12 significant digits.
"""
import csv
import os
import re
import subprocess
import sys

import h5py
import numpy as np

SIGMA = 5.670374419e-8
TOLERANCE_K = 2e-6
NUMBER = r"[-+0-9.eE]+"


def solve(temperature0, fixed, q, gl, gr, sigma):
    """Steady state of a network; gl and gr are lists of (i, j, value), sigma multiplies gr."""
    t = np.where(fixed, temperature0, 250.0)
    free = ~fixed
    for _ in range(200):
        f = q.copy()
        jac = np.zeros((len(t), len(t)))
        for i, j, g in gl:
            f[i] += g * (t[j] - t[i]); f[j] += g * (t[i] - t[j])
            jac[i, i] -= g; jac[i, j] += g; jac[j, j] -= g; jac[j, i] += g
        for i, j, g in gr:
            s = sigma * g
            f[i] += s * (t[j] ** 4 - t[i] ** 4); f[j] += s * (t[i] ** 4 - t[j] ** 4)
            jac[i, i] -= 4 * s * t[i] ** 3; jac[i, j] += 4 * s * t[j] ** 3
            jac[j, j] -= 4 * s * t[j] ** 3; jac[j, i] += 4 * s * t[i] ** 3
        step = np.linalg.solve(jac[np.ix_(free, free)], -f[free])
        t[free] += np.clip(step, -50.0, 50.0)
        if np.max(np.abs(step)) < 1e-10:
            return t
    raise RuntimeError("Newton did not converge")


def read_esatan(path):
    text = open(path).read()
    absolute = float(re.search(rf"TABS = ({NUMBER});", text).group(1))
    stefan = float(re.search(rf"STEFAN = ({NUMBER});", text).group(1))
    nodes = {}
    for kind, number, rest in re.findall(r"^\s*([DXB])(\d+) = '[^']*', (.*);$", text, re.M):
        fields = dict((k.strip(), float(v)) for k, v in (p.split("=") for p in rest.split(",")))
        q = sum(fields.get(k, 0.0) for k in ("QS", "QA", "QE", "QI"))
        nodes[int(number)] = (fields["T"] + absolute, kind == "B", q)
    conductors = {kind: [(int(a), int(b), float(v)) for a, b, v in
                         re.findall(rf"^\s*{kind}\((\d+), (\d+)\) = ({NUMBER});", text, re.M)] for kind in ("GL", "GR")}
    return nodes, conductors["GL"], conductors["GR"], stefan


def read_sinda(path):
    lines = open(path).read().splitlines()
    absolute = -float(next(re.search(rf"ABSZRO = ({NUMBER})", l).group(1) for l in lines if "ABSZRO" in l))
    sigma = float(next(re.search(rf"SIGMA = ({NUMBER})", l).group(1) for l in lines if "SIGMA =" in l))
    block, nodes, gl, gr, q = None, {}, [], [], {}
    for line in lines:
        if line.startswith("HEADER"):
            block = line.split()[1]
            continue
        data = line.split("$")[0].strip()
        if not data or line.startswith("C "):
            continue
        values = [v.strip() for v in data.split(",")]
        if block == "NODE":
            number = int(values[0])
            nodes[abs(number)] = (float(values[1]) + absolute, number < 0, 0.0)
        elif block == "CONDUCTOR":
            (gr if int(values[0]) < 0 else gl).append((int(values[1]), int(values[2]), float(values[3])))
        elif block == "SOURCE":
            q[int(values[0])] = q.get(int(values[0]), 0.0) + float(values[1])
    nodes = {k: (t, fixed, q.get(k, 0.0)) for k, (t, fixed, _) in nodes.items()}
    return nodes, gl, gr, sigma


def read_csv(directory):
    nodes = {}
    with open(os.path.join(directory, "nodes.csv")) as f:
        for row in csv.DictReader(f):
            q = sum(float(row[k]) for k in ("q_solar_W", "q_albedo_W", "q_earth_ir_W", "q_internal_W"))
            nodes[int(row["index"])] = (float(row["temperature_K"]), row["fixed"] == "1", q)
    gl, gr = [], []
    with open(os.path.join(directory, "conductors.csv")) as f:
        for row in csv.DictReader(f):
            (gl if row["kind"] == "GL" else gr).append((int(row["node_a"]), int(row["node_b"]), float(row["value"])))
    return nodes, gl, gr, SIGMA


def deck_solution(nodes, gl, gr, sigma):
    """Solves a parsed deck; returns temperatures by node number."""
    numbers = sorted(nodes)
    index = {n: k for k, n in enumerate(numbers)}
    t0 = np.array([nodes[n][0] for n in numbers])
    fixed = np.array([nodes[n][1] for n in numbers])
    q = np.array([nodes[n][2] for n in numbers])
    t = solve(t0, fixed, q, [(index[a], index[b], g) for a, b, g in gl], [(index[a], index[b], g) for a, b, g in gr],
              sigma)
    return dict(zip(numbers, t))


def check(radnet, h5, label, extra, failures):
    expected = None
    with h5py.File(h5) as f:
        position = int(extra[extra.index("--position") + 1]) if "--position" in extra else 0
        expected = f["solution/temperature"][position]
    base = os.path.splitext(h5)[0] + "-" + label
    for fmt, out, reader, first in (("esatan", base + ".d", read_esatan, 1), ("sinda", base + ".sin", read_sinda, 1),
                                    ("csv", base + "-csv", read_csv, 0)):
        subprocess.run([radnet, "export", h5, "--format", fmt, "-o", out] + extra, check=True, capture_output=True)
        t = deck_solution(*reader(out))
        got = np.array([t[k + first] for k in range(len(expected))])
        worst = np.max(np.abs(got - expected))
        print(f"{label} {fmt}: largest |T_deck − T_radnet| = {worst:.3e} K over {len(expected)} nodes")
        if not worst <= TOLERANCE_K:
            failures.append(f"{label} {fmt}: {worst:.3e} K")


def steady_cubesat(source, work):
    """The hot/cold CubeSat, steady per position, 12 positions, fewer rays, no samples."""
    text = open(os.path.join(source, "cases/examples/cubesat-hot-cold.yaml")).read()
    text = re.sub(r"^\s*transient:.*$", "", text, flags=re.M)
    text = re.sub(r"^uncertainty:.*$", "", text, flags=re.M)
    text = text.replace("positions: 72", "positions: 12").replace("rays: 50000", "rays: 5000")
    path = os.path.join(work, "cubesat-steady.yaml")
    open(path, "w").write(text)
    return path


def main(radnet, source, work):
    os.makedirs(work, exist_ok=True)
    failures = []
    lumped = os.path.join(work, "lumped.h5")
    subprocess.run([radnet, "run", os.path.join(source, "cases/analytic/lumped-nodes.yaml"), "-o", lumped, "-q"],
                   check=True, capture_output=True)
    check(radnet, lumped, "lumped", [], failures)
    cubesat = os.path.join(work, "cubesat.h5")
    subprocess.run([radnet, "run", steady_cubesat(source, work), "-o", cubesat, "-q"], check=True, capture_output=True)
    with h5py.File(cubesat) as f:
        start = f["cases/position_start"][()]
        heater = f["solution/heat/heater"][()]
    check(radnet, cubesat, "hot", ["--case", "hot", "--position", str(start[0] + 3)], failures)
    # The cold case where the battery heater is on, if it ever is: a fixed power in the deck.
    on = [p for p in range(start[1], start[2]) if heater[p].max() > 0]
    check(radnet, cubesat, "cold", ["--case", "cold", "--position", str(on[0] if on else start[1] + 6)], failures)
    # Bad input exits 2 with the reason, and writes nothing.
    not_h5 = os.path.join(work, "not-a-result.h5")
    open(not_h5, "w").write("hello")
    for args, reason in (([not_h5], "not an HDF5 file"), ([cubesat, "--case", "tepid"], "no design case 'tepid'"),
                         ([cubesat, "--position", "9999"], "is not a position of"),
                         ([cubesat, "--min-gr", "1.5"], "--min-gr must be in [0, 1)")):
        out = os.path.join(work, "refused.d")
        run = subprocess.run([radnet, "export", *args, "-o", out], capture_output=True, text=True)
        if run.returncode != 2 or reason not in run.stderr or os.path.exists(out):
            failures.append(f"export {args[1:]}: exit {run.returncode}, stderr {run.stderr!r}, expected 2 and '{reason}'")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
