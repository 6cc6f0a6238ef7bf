#!/usr/bin/python3
"""The loads stage of two radnet builds on the same cases, one after the other in one session:
each case at default settings (its `solver:` block removed) flown nadir, Sun-pointing and
inertial, both builds alternating, the best of the repeats. Reported per case and attitude:
the loads stage (s, and ms a position), the sky kernel's rays, the loads' part of the largest
absorbed-power σ (of the node's orbit maximum), the nodes over the budget, and how the two
builds' absorbed powers differ against their combined σ (99th percentile and largest of
abs(Δ)/σ over node-positions with σ > 0; the builds share their first rays, so the two are
not independent and the differences are smaller than independent runs' would be).

usage: bench_loads_builds.py BASELINE_RADNET RADNET OUT.md CASE.yaml... [--repeats R]
       [--attitudes nadir,sun,inertial] [--once CASE.yaml...]  (--once: one repeat, nadir and inertial)
"""
import os
import platform
import re
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ATTITUDES = {
    "nadir": None,
    "sun": "attitude: {mode: sun}",
    "inertial": "attitude: {mode: inertial, quaternion: [1, 0, 0, 0]}",
}


def variant(path, attitude):
    """The case at default settings in the given attitude, beside it (its includes resolve)."""
    text = re.sub(r"^solver:[^\n]*\n?(  [^\n]*(\n|$))*", "", open(path).read(), flags=re.M)
    if ATTITUDES[attitude]:
        text = re.sub(r"^attitude:.*$", ATTITUDES[attitude], text, flags=re.M)
    fd, name = tempfile.mkstemp(suffix="-loads.yaml", dir=os.path.dirname(os.path.abspath(path)))
    with os.fdopen(fd, "w") as f:
        f.write(text)
    return name


def run(radnet, case, out):
    proc = subprocess.run([radnet, "run", case, "-o", out, "-q"], capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{case}: {radnet} exited {proc.returncode}\n{proc.stderr[-2000:]}")
    with h5py.File(out) as h5:
        rep = dict(h5["/report"].attrs)
        q = h5["/loads/solar"][()] + h5["/loads/albedo"][()] + h5["/loads/earth_ir"][()]
        sigma = h5["/uncertainty/absorbed_power"][()]
        triangles = int(h5["/geometry/triangles"].shape[0]) if "/geometry/triangles" in h5 else 0
    return rep, q, sigma, triangles


def number(rep, key):
    v = rep.get(key, 0)
    return float(v[()] if hasattr(v, "shape") else v)


def compare(base_radnet, radnet, path, attitude, repeats, rows):
    case = variant(path, attitude)
    tmp = tempfile.mkdtemp()
    try:
        best = {}
        for _ in range(repeats):
            for label, exe in (("base", base_radnet), ("new", radnet)):
                rep, q, sigma, tri = run(exe, case, os.path.join(tmp, label + ".h5"))
                t = number(rep, "time_environment_loads_s")
                if label not in best or t < best[label][0]:
                    best[label] = (t, rep, q, sigma, tri)
        (tb, rb, qb, sb, tri), (tn, rn, qn, sn, _) = best["base"], best["new"]
        combined = np.hypot(sb, sn)
        mask = combined > 0
        ratio = np.abs(qb - qn)[mask] / combined[mask]
        positions, nodes = qb.shape  # /loads/* are (positions, nodes)
        rows.append([os.path.basename(path), str(nodes), str(tri), attitude,
                     "%.3g" % tb, "%.3g" % tn, "%.2f×" % (tb / tn if tn > 0 else float("nan")),
                     "%.3g" % (1e3 * tn / positions),
                     "%.3g / %.3g" % (number(rb, "sky_kernel_rays") / 1e6, number(rn, "sky_kernel_rays") / 1e6),
                     "%.3g / %.3g" % (number(rb, "planet_rays") / 1e6, number(rn, "planet_rays") / 1e6),
                     "%.3f / %.3f" % (100 * number(rb, "absorbed_uncertainty_loads_max_relative"),
                                      100 * number(rn, "absorbed_uncertainty_loads_max_relative")),
                     "%d / %d" % (number(rb, "nodes_over_budget"), number(rn, "nodes_over_budget")),
                     "%.2f / %.2f" % (np.percentile(ratio, 99), ratio.max()) if ratio.size else "–"])
        print(" | ".join(rows[-1]), flush=True)
    finally:
        os.unlink(case)
        for f in os.listdir(tmp):
            os.unlink(os.path.join(tmp, f))
        os.rmdir(tmp)


def main():
    args = sys.argv[1:]
    if len(args) < 4:
        raise SystemExit(__doc__)
    base_radnet, radnet, out = args[:3]
    cases, once, repeats, attitudes, k = [], [], 2, ["nadir", "sun", "inertial"], 3
    while k < len(args):
        if args[k] == "--repeats":
            repeats, k = int(args[k + 1]), k + 2
        elif args[k] == "--attitudes":
            attitudes, k = args[k + 1].split(","), k + 2
        elif args[k] == "--once":
            once, k = args[k + 1:], len(args)
        else:
            cases.append(args[k])
            k += 1
    rows = []
    t0 = time.monotonic()
    for path in cases:
        for attitude in attitudes:
            compare(base_radnet, radnet, path, attitude, repeats, rows)
    for path in once:
        for attitude in ("nadir", "inertial"):
            compare(base_radnet, radnet, path, attitude, 1, rows)
    head = ["case", "nodes", "triangles", "attitude", "baseline loads (s)", "loads (s)", "faster",
            "ms a position", "kernel rays (M), base / new", "planet rays (M)", "loads' σ, % of orbit max",
            "nodes over budget", "abs(Δ)/σ 99 % / largest"]
    with open(out, "w") as f:
        f.write("# Loads stage: this build against a baseline build\n\n")
        f.write("Generated by `bench/bench_loads_builds.py %s %s %s ...` in %.0f s. Machine: %s, %d cores, "
                "Debian 12, both builds on all cores (OpenMP), one after the other per case; default settings "
                "(the cases' `solver:` blocks removed: accuracy 0.01, the loads' share 0.005); timings are the "
                "best of the repeats (--once cases: one run). abs(Δ)/σ: the two builds' absorbed power per "
                "node-position against both σ combined (they share their first rays: not independent).\n\n"
                % (os.path.basename(base_radnet), os.path.basename(radnet), os.path.basename(out),
                   time.monotonic() - t0, platform.processor() or platform.machine(), os.cpu_count()))
        f.write("| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n")
        for r in rows:
            f.write("| " + " | ".join(r) + " |\n")


if __name__ == "__main__":
    main()
