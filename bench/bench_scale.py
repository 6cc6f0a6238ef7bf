#!/usr/bin/python3
"""radnet at scale: wall time, peak memory, file size, F's density and the absorbed-power
uncertainty of `radnet run` against the number of nodes, with the growth fitted as
time ∝ n^p (least squares on log-log), and the file against what dense n × n matrices would
take. Each case as written (bench/cases pin `method: monte_carlo, rays: 4000`) and, with
--defaults, also with its `solver:` block removed (the defaults a user gets).

usage: bench_scale.py RADNET OUT.md CASE.yaml... [--defaults CASE.yaml...]
"""
import os
import re
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np


def defaults_copy(path):
    """The case without its solver block, beside it (its includes resolve)."""
    text = re.sub(r"^solver:[^\n]*\n?(  [^\n]*(\n|$))*", "", open(path).read(), flags=re.M)
    fd, name = tempfile.mkstemp(suffix="-defaults.yaml", dir=os.path.dirname(os.path.abspath(path)))
    with os.fdopen(fd, "w") as f:
        f.write(text)
    return name


def run(radnet, case, label):
    out = tempfile.mktemp(suffix=".h5")
    # A child Python of its own runs radnet: its RUSAGE_CHILDREN peak is this run's alone.
    probe = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:]); "
             "sys.stderr.write('peak_kib %d\\n' % resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); "
             "sys.exit(r.returncode)")
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, "-c", probe, radnet, "run", case, "-o", out], capture_output=True,
                          text=True)
    wall = time.monotonic() - t0
    if proc.returncode != 0:
        raise SystemExit(f"{case}: radnet exited {proc.returncode}\n{proc.stderr[-2000:]}")
    peak = int(re.search(r"peak_kib (\d+)", proc.stderr).group(1)) * 1024
    m = re.search(r"wrote .* in ([0-9.]+) s", proc.stderr)
    size = os.path.getsize(out)
    with h5py.File(out) as h5:
        rep = dict(h5["/report"].attrs)
        n = h5["/nodes/name"].shape[0]
        nnz = h5["/network/sparse/view_factors/data"].shape[0]
        rank = int(h5["/eigen"].attrs["rank"])
        method = h5["/network"].attrs["method"]
    for f in (out, out[:-3] + ".xmf"):
        if os.path.exists(f):
            os.unlink(f)
    stages = {k[5:-2]: float(v) for k, v in rep.items() if k.startswith("time_") and k.endswith("_s")}
    stages["output"] = float(m.group(1)) if m else 0.0
    return {"label": label, "n": n, "wall": wall, "peak": peak, "size": size, "nnz": nnz, "rank": rank,
            "method": method, "stages": stages, "sigma": float(rep.get("absorbed_uncertainty_max_relative", np.nan)),
            "over": int(rep.get("nodes_over_budget", -1))}


def fit(rows):
    if len(rows) < 2:
        return float("nan")
    n = np.log([r["n"] for r in rows])
    t = np.log([r["wall"] for r in rows])
    return float(np.polyfit(n, t, 1)[0])


def machine():
    cpu = "unknown CPU"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    mem = int(open("/proc/meminfo").readline().split()[1]) / 1024 ** 2
    return f"{cpu}, {os.cpu_count()} cores, {mem:.1f} GiB, Debian 12"


def table(rows):
    keys = ["view_factors", "eigendecomposition", "exchange_factors", "band_solves", "environment_loads",
            "uncertainty", "output"]
    lines = ["| case | n | F non-zero | rank | wall s | peak GB | file MB | dense n² matrices GB | file / dense | "
             "output / wall | max σ / P_max | nodes over | " + " | ".join(keys) + " |",
             "|" + "---|" * (12 + len(keys))]
    for r in rows:
        dense = 5 * 8.0 * r["n"] ** 2  # F, raw F, σ(F), G, GR
        lines.append(
            f"| {r['label']} | {r['n']:,} | {r['nnz'] / r['n'] ** 2:.2%} | {r['rank']} | {r['wall']:.1f} | "
            f"{r['peak'] / 1e9:.2f} | {r['size'] / 1e6:.0f} | {dense / 1e9:.1f} | {r['size'] / dense:.2%} | "
            f"{r['stages']['output'] / r['wall']:.1%} | {r['sigma']:.3%} | {r['over']} | " +
            " | ".join(f"{r['stages'].get(k, 0.0):.2f}" for k in keys) + " |")
    return "\n".join(lines)


def main():
    radnet, out_md = sys.argv[1], sys.argv[2]
    args = sys.argv[3:]
    pinned, defaults = (args[:args.index("--defaults")], args[args.index("--defaults") + 1:]) \
        if "--defaults" in args else (args, [])
    rows = [run(radnet, c, os.path.basename(c)[:-5]) for c in pinned]
    default_rows = []
    for c in defaults:
        copy = defaults_copy(c)
        try:
            default_rows.append(run(radnet, copy, os.path.basename(c)[:-5] + " (defaults)"))
        finally:
            os.unlink(copy)
    with open(out_md, "w") as f:
        f.write("# radnet at scale\n\n")
        f.write(f"Machine: {machine()}. Written by `bench/bench_scale.py` (`make bench-scale`); each row one "
                "`radnet run` of the whole case (wall clock of the process; peak resident memory from "
                "`getrusage`; file = the .h5). Stage times in s from `/report`, `output` the write.\n\n")
        f.write("## The bench satellites as written (`method: monte_carlo, rays: 4000`)\n\n")
        f.write(table(rows) + "\n\n")
        f.write(f"Wall time grows as n^{fit(rows):.2f} (least squares on log-log over these rows).\n\n")
        if default_rows:
            f.write("## The same models at the defaults (`solver:` removed: method auto, accuracy 0.01)\n\n")
            f.write(table(default_rows) + "\n\n")
        f.write("`dense n² matrices` is what F, its raw estimate, σ(F), G and GR would take as (n, n) "
                "datasets of doubles; `max σ / P_max` is `/report absorbed_uncertainty_max_relative` (the "
                "largest over nodes of the absorbed power's 1σ over its orbit maximum; the case asks 1 %).\n")
    print(open(out_md).read())


if __name__ == "__main__":
    main()
