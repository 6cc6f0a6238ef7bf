#!/usr/bin/python3
"""View factors at default settings on several shapes of model (issue 30).

Usage: bench_view_factor_defaults.py RADNET OUT.md [VIEW3D]

Each model is run as a user would run it (`radnet run case.yaml`, solver.accuracy 0.01,
method auto, nothing pinned); the view-factor stage's time comes from /report
(time_view_factors_s, against auto's prediction time_view_factors_predicted_s), the whole
process is timed with its peak memory (/usr/bin/time). Rooms: every cell of every face a
node; View3D 4.0 (built from ../shared/peers/view3d/build.sh, only run) computes the same
surfaces, timed as its whole process and by its own log. Error at face level: cells summed
into faces (sum over i in a, j in b of A_i F_ij / A_a) against Howell C-11/C-14.
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOM = [  # name, origin, u, v (u x v into the room)
    ("floor", (0, 0, 0), (5, 0, 0), (0, 3, 0)),
    ("wx0", (0, 0, 0), (0, 3, 0), (0, 0, 2.5)),
    ("wx5", (5, 0, 0), (0, 0, 2.5), (0, 3, 0)),
    ("wy0", (0, 0, 0), (0, 0, 2.5), (5, 0, 0)),
    ("wy3", (0, 3, 0), (5, 0, 0), (0, 0, 2.5)),
    ("ceil", (0, 0, 2.5), (0, 3, 0), (5, 0, 0)),
]


def parallel(a, b, c):  # Howell C-11
    x, y = a / c, b / c
    x1, y1 = 1 + x * x, 1 + y * y
    return 2 / (math.pi * x * y) * (math.log(math.sqrt(x1 * y1 / (1 + x * x + y * y)))
                                    + x * math.sqrt(y1) * math.atan(x / math.sqrt(y1))
                                    + y * math.sqrt(x1) * math.atan(y / math.sqrt(x1))
                                    - x * math.atan(x) - y * math.atan(y))


def perpendicular(l, w, h):  # Howell C-14: common edge l, widths w (from) and h (to)
    H, W = h / l, w / l
    a = (1 + W * W) * (1 + H * H) / (1 + W * W + H * H)
    b = W * W * (1 + W * W + H * H) / ((1 + W * W) * (W * W + H * H))
    c = H * H * (1 + H * H + W * W) / ((1 + H * H) * (H * H + W * W))
    return 1 / (math.pi * W) * (W * math.atan(1 / W) + H * math.atan(1 / H)
                                - math.sqrt(H * H + W * W) * math.atan(1 / math.sqrt(H * H + W * W))
                                + 0.25 * math.log(a * b ** (W * W) * c ** (H * H)))


def face_closed_form(a, b):
    """F from face a to face b of the room (they are parallel or share an edge)."""
    (_, oa, ua, va), (_, ob, ub, vb) = ROOM[a], ROOM[b]
    ext = lambda u, v: [abs(u[k]) + abs(v[k]) for k in range(3)]
    ea, eb = ext(ua, va), ext(ub, vb)
    na = [k for k in range(3) if ea[k] == 0][0]
    nb = [k for k in range(3) if eb[k] == 0][0]
    if na == nb:
        dims = [ea[k] for k in range(3) if k != na]
        return parallel(dims[0], dims[1], abs(oa[na] - ob[na]))
    common = [k for k in range(3) if k != na and k != nb][0]
    return perpendicular(ea[common], ea[nb], eb[na])


def room_case(k, path):
    with open(path, "w") as f:
        f.write("name: room-%d\nmaterials:\n  grey: {emissivity: 0.9, absorptivity: 0.5}\ngeometry:\n" % k)
        for name, o, u, v in ROOM:
            f.write("  - rectangle: {name: %s, origin: %s, u: %s, v: %s, front: grey, subdivisions: [%d, %d], "
                    "nodes: [%d, %d]}\n" % (name, list(o), list(u), list(v), k, k, k, k))


def view3d_input(k, path):
    verts, index, surfs = [], {}, []
    for fi, (name, o, u, v) in enumerate(ROOM):
        def vid(i, j):
            p = tuple(round(o[d] + u[d] * i / k + v[d] * j / k, 12) for d in range(3))
            if p not in index:
                index[p] = len(verts) + 1
                verts.append(p)
            return index[p]
        for i in range(k):
            for j in range(k):
                surfs.append((vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1), name))
    with open(path, "w") as f:
        f.write("T room %d x %d per face\nC encl=1\nF 3\n" % (k, k))
        for n, p in enumerate(verts, 1):
            f.write("V %d %.12g %.12g %.12g\n" % (n, *p))
        for n, s in enumerate(surfs, 1):
            f.write("S %d %d %d %d %d 0 0 0.9 %s\n" % (n, *s[:4], s[4]))
        f.write("End of data\n")


def face_error(F, area, k):
    """Largest |face-level F − closed form| over the 30 ordered face pairs."""
    cells = k * k
    worst = 0.0
    for a in range(6):
        ra = slice(a * cells, (a + 1) * cells)
        aa = area[ra].sum()
        for b in range(6):
            if a == b:
                continue
            rb = slice(b * cells, (b + 1) * cells)
            fab = (area[ra, None] * F[ra, rb]).sum() / aa
            worst = max(worst, abs(fab - face_closed_form(a, b)))
    return worst


def defaults_copy(case, tmp, name):
    """The case with its `solver:` block removed (default settings), file and include paths
    made absolute so that the copy runs from the temporary directory."""
    base = os.path.dirname(os.path.abspath(case))
    lines, out = open(case).read().splitlines(), []
    skipping = False
    for line in lines:
        if line.startswith("solver:"):
            skipping = True
            continue
        if skipping and (line.startswith(" ") or not line.strip()):
            continue
        skipping = False
        line = re.sub(r"(file|include): ([^,}\s]+)", lambda m: "%s: %s" % (m.group(1), os.path.join(base, m.group(2))), line)
        out.append(line)
    path = os.path.join(tmp, name + ".yaml")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return path


def run_radnet(radnet, case, out):
    t0 = time.time()
    p = subprocess.run(["/usr/bin/time", "-f", "%M", radnet, "run", case, "-o", out, "-q"],
                       capture_output=True, text=True)
    wall = time.time() - t0
    if p.returncode != 0:
        raise RuntimeError(case + ": " + p.stderr[-2000:])
    peak_mb = int(p.stderr.strip().splitlines()[-1]) / 1024
    with h5py.File(out) as f:
        r = f["/report"].attrs
        net = f["/network"].attrs
        row = {"wall": wall, "peak": peak_mb, "vf": float(r["time_view_factors_s"]),
               "predicted": float(r.get("time_view_factors_predicted_s", float("nan"))),
               "nodes": len(f["/nodes/area"]), "pairs": int(net.get("exact_pairs_unoccluded", 0)),
               "quadrature": int(net.get("exact_pairs_by_quadrature", 0)),
               "sampled": int(net.get("rows_sampled", 0)), "stderr": float(r["view_factor_error"])}
    return row


def read_view3d(path, n):
    with open(path) as f:
        f.readline()
        data = np.array(f.read().split(), dtype=float)
    area = data[:n]
    F = data[n:n + n * n].reshape(n, n)
    return area, F


def run_view3d(exe, vs3, out):
    t0 = time.time()
    # in the model's temporary directory: View3D writes its View3D.log where it runs
    p = subprocess.run([exe, vs3, out], capture_output=True, text=True, cwd=os.path.dirname(vs3) or ".")
    wall = time.time() - t0
    m = re.search(r"([0-9.e+-]+) seconds to compute view factors", p.stdout + p.stderr)
    return wall, float(m.group(1)) if m else float("nan")


ROOM_REPEATS = 3


def main():
    radnet, out_md = os.path.abspath(sys.argv[1]), sys.argv[2]
    view3d = os.path.abspath(sys.argv[3]) if len(sys.argv) > 3 else ""  # run in its temporary directory
    here = os.path.dirname(os.path.abspath(__file__))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in (16, 32):
            case = os.path.join(tmp, "room%d.yaml" % k)
            room_case(k, case)
            h5 = os.path.join(tmp, "room%d.h5" % k)
            vs3, vout = os.path.join(tmp, "room%d.vs3" % k), os.path.join(tmp, "room%d.out" % k)
            if view3d:
                view3d_input(k, vs3)
            # ROOM_REPEATS runs of each, alternated: on this machine a run's time moves by 10–40 %
            # with what ran before it (memory a process touches first costs most when the
            # host has taken it back, docs/benchmarks.md "Fresh memory"); the medians are kept.
            runs, v3_runs = [], []
            for _ in range(ROOM_REPEATS):
                runs.append(run_radnet(radnet, case, h5))
                if view3d:
                    v3_runs.append(run_view3d(view3d, vs3, vout))
            r = sorted(runs, key=lambda x: x["vf"])[len(runs) // 2]
            r["vf_range"] = (min(x["vf"] for x in runs), max(x["vf"] for x in runs))
            with h5py.File(h5) as f:
                r["error"] = face_error(f["/network/view_factors"][:], f["/nodes/area"][:], k)
            r["model"] = "room %d × %d cells per face" % (k, k)
            if view3d:
                r["v3_wall"], r["v3_compute"] = sorted(v3_runs)[len(v3_runs) // 2]
                r["v3_range"] = (min(w for w, _ in v3_runs), max(w for w, _ in v3_runs))
                area, F = read_view3d(vout, 6 * k * k)
                r["v3_error"] = face_error(F, area, k)
                os.remove(vout)
            rows.append(r)
        cases = os.path.join(here, "cases")
        shapes = [("coaxial cylinders r2/r1 = 1.5, annulus caps", os.path.join(cases, "coaxial-cylinders.yaml")),
                  ("satellite: bus cells, wings, dish", os.path.join(cases, "satellite-1602.yaml")),
                  ("satellite, finer cells", os.path.join(cases, "satellite-6402.yaml")),
                  ("CAD assembly in mm (NASTRAN bus, STL wings)",
                   os.path.join(here, "..", "cases", "examples", "mesh-assembly.yaml"))]
        for k, (name, case) in enumerate(shapes):
            r = run_radnet(radnet, defaults_copy(case, tmp, "shape%d" % k), os.path.join(tmp, "shape.h5"))
            r["model"] = name
            rows.append(r)
        # The cylinders again with `method: exact` (every pair integrated, the occluded ones by
        # the worst-first quadrature): it ran for more than 420 s before that refinement.
        exact = defaults_copy(os.path.join(cases, "coaxial-cylinders.yaml"), tmp, "cylinders-exact")
        with open(exact, "a") as f:
            f.write("solver: {view_factors: {method: exact}}\n")
        r = run_radnet(radnet, exact, os.path.join(tmp, "exact.h5"))
        r["model"] = "coaxial cylinders, `method: exact`"
        rows.insert(3, r)
        pinned = os.path.join(here, "cases", "satellite-1602.yaml")
        base = run_radnet(radnet, pinned, os.path.join(tmp, "pinned.h5"))
    with open(out_md, "w") as f:
        f.write("# View factors at default settings\n\nGenerated by `bench/bench_view_factor_defaults.py` "
                "(`make bench`). Machine: AMD EPYC, 2 cores, 24 GiB, Debian 12; radnet on 2 threads "
                "(its default), View3D 4.0 on one (it has no threads). Default settings: solver.accuracy "
                "0.01, method auto, nothing pinned.\n\n")
        f.write("| model | nodes | VF stage (s) | predicted (s) | whole run (s) | peak (MiB) | exact pairs "
                "(by point rules) | rows by rays | face error | largest σ_F | View3D whole (compute) (s) "
                "| View3D face error |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            v3 = ("%.2f (%.2f)" % (r["v3_wall"], r["v3_compute"])) if "v3_wall" in r else "–"
            v3e = ("%.2e" % r["v3_error"]) if "v3_error" in r else "–"
            err = ("%.2e" % r["error"]) if "error" in r else "–"
            predicted = "–" if math.isnan(r["predicted"]) else "%.3f" % r["predicted"]  # method exact: no plan
            f.write("| %s | %d | %.3f | %s | %.2f | %.0f | %d (%d) | %d | %s | %.2e | %s | %s |\n" % (
                r["model"], r["nodes"], r["vf"], predicted, r["wall"], r["peak"], r["pairs"],
                r["quadrature"], r["sampled"], err, r["stderr"], v3, v3e))
        f.write("\nBaseline in the same run: the 1,602-node satellite with `method: monte_carlo, rays: 4000` "
                "(bench/cases/satellite-1602.yaml): view factors %.3f s, whole run %.2f s, largest σ_F %.2e.\n"
                % (base["vf"], base["wall"], base["stderr"]))

        f.write("\nThe rooms are run %d times each, radnet and View3D alternated; the table gives the run of "
                "median view-factor stage and View3D's median whole process. Their ranges, and the ratio of "
                "View3D's whole process to radnet's view-factor stage (medians):\n\n"
                "| model | radnet VF stage, min–max (s) | View3D whole, min–max (s) | ratio |\n|---|---|---|---|\n"
                % ROOM_REPEATS)
        for r in rows:
            if "v3_range" in r:
                f.write("| %s | %.3f–%.3f | %.2f–%.2f | %.1f× |\n" % (
                    r["model"], r["vf_range"][0], r["vf_range"][1], r["v3_range"][0], r["v3_range"][1],
                    r["v3_wall"] / r["vf"]))

if __name__ == "__main__":
    main()
