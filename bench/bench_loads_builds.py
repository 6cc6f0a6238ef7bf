#!/usr/bin/python3
"""The loads stage of two radnet builds on the same cases, one after the other in one session:
each case at default settings (its `solver:` block removed) flown nadir, Sun-pointing and
inertial, both builds alternating, the best of the repeats. Reported per case and attitude:
the loads stage (s, and ms a position), the sky kernel's rays, the loads' part of the largest
absorbed-power σ (of the node's orbit maximum), the nodes over the budget, and how the two
builds' absorbed powers differ against their combined σ (99th percentile and largest of
abs(Δ)/σ over node-positions with σ > 0; the builds share their first rays, so the two are
not independent and the differences are smaller than independent runs' would be).

usage: bench_loads_builds.py BASELINE_RADNET RADNET OUT.md CASE.yaml... [--repeats R] [--reference]
       [--attitudes nadir,sun,inertial] [--once CASE.yaml...]  (--once: one repeat, nadir and inertial)

--reference: each case Sun-pointing and inertial is also run by RADNET at solver.accuracy 0.001 (ten
times the default's), and both builds' absorbed powers are read against it: abs(Δ)/σ (σ of the
build and of the reference combined) should exceed 4 at about 0.006 % of node-positions for
Gaussian errors.
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


def variant(path, attitude, accuracy=None):
    """The case at default settings in the given attitude, beside it (its includes resolve);
    with `accuracy`, solver.accuracy set to it (the reference run)."""
    text = re.sub(r"^solver:[^\n]*\n?(  [^\n]*(\n|$))*", "", open(path).read(), flags=re.M)
    if ATTITUDES[attitude]:
        text = re.sub(r"^attitude:.*$", ATTITUDES[attitude], text, flags=re.M)
    if accuracy:
        text = text.rstrip("\n") + "\nsolver: {accuracy: %g}\n" % accuracy
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


def calibration(q, sigma, qr, sr):
    """abs(Δ)/σ against the reference (σ both combined): 99th percentile, largest, share over 4."""
    combined = np.hypot(sigma, sr)
    mask = combined > 0
    r = np.abs(q - qr)[mask] / combined[mask]
    return "%.2f / %.2f / %.3f" % (np.percentile(r, 99), r.max(), 100 * (r > 4).mean())


def compare(base_radnet, radnet, path, attitude, repeats, rows, reference=False):
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
        if reference and attitude != "nadir":
            ref_case = variant(path, attitude, accuracy=0.001)
            try:
                _, qr, sr, _ = run(radnet, ref_case, os.path.join(tmp, "ref.h5"))
            finally:
                os.unlink(ref_case)
            rows[-1] += [calibration(qb, sb, qr, sr), calibration(qn, sn, qr, sr)]
        else:
            rows[-1] += ["–", "–"]
        print(" | ".join(rows[-1]), flush=True)
    finally:
        os.unlink(case)
        for f in os.listdir(tmp):
            os.unlink(os.path.join(tmp, f))
        os.rmdir(tmp)


def machine():
    """The processor's model name, as /proc/cpuinfo gives it."""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main():
    args = sys.argv[1:]
    if len(args) < 4:
        raise SystemExit(__doc__)
    base_radnet, radnet, out = args[:3]
    cases, once, repeats, attitudes, k, reference = [], [], 2, ["nadir", "sun", "inertial"], 3, False
    while k < len(args):
        if args[k] == "--reference":
            reference, k = True, k + 1
        elif args[k] == "--repeats":
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
            compare(base_radnet, radnet, path, attitude, repeats, rows, reference)
    for path in once:
        for attitude in ("nadir", "inertial"):
            compare(base_radnet, radnet, path, attitude, 1, rows)
    head = ["case", "nodes", "triangles", "attitude", "baseline loads (s)", "loads (s)", "faster",
            "ms a position", "kernel rays (M), base / new", "planet rays (M)", "loads' σ, % of orbit max",
            "nodes over budget", "abs(Δ)/σ 99 % / largest", "baseline vs reference: 99 % / largest / % over 4",
            "this build vs reference"]
    with open(out, "w") as f:
        f.write("# Loads stage: this build against a baseline build\n\n")
        f.write("Generated by `bench/bench_loads_builds.py %s %s %s %s` in %.0f s. Machine: %s, %d cores, "
                "Debian 12, both builds on all cores (OpenMP), one after the other per case; default settings "
                "(the cases' `solver:` blocks removed: accuracy 0.01, the loads' share 0.005); timings are the "
                "best of the repeats (--once cases: one run). abs(Δ)/σ: the two builds' absorbed power per "
                "node-position against both σ combined (they share their first rays: not independent).\n\n"
                % (os.path.basename(base_radnet), os.path.basename(radnet), out, " ".join(args[3:]),
                   time.monotonic() - t0, machine(), os.cpu_count()))
        f.write("| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n")
        for r in rows:
            f.write("| " + " | ".join(r) + " |\n")


if __name__ == "__main__":
    main()
