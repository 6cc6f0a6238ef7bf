#!/usr/bin/python3
"""Issue 34's benchmark: parts that turn against the same model with them fixed.

usage: bench_articulation.py RADNET OUT.md CASE.yaml [CASE.yaml ...]

Each case (with `articulation:`) is run as written and with its `articulation:` block removed
(the parts fixed as written), default settings, whole process wall time; the ratio is the
issue's measure (≤ 2×). Accuracy against runs with the parts turned by hand is tested on a
small model (tests/check_articulation.py), not here. The machine is described from /proc.
"""
import os
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

RADNET, OUT, CASES = sys.argv[1], sys.argv[2], sys.argv[3:]


def run(path, out):
    t0 = time.perf_counter()
    r = subprocess.run([RADNET, "run", path, "-o", out, "-q"], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise SystemExit("%s: exit %d\n%s" % (path, r.returncode, r.stderr))
    return wall, h5py.File(out, "r")


def without_articulation(text):
    a = text.index("\narticulation:\n") + 1
    b = text.index("\norbit:\n") + 1
    return text[:a] + text[b:]


def stages(f):
    return {k[5:-2]: float(v) for k, v in f["report"].attrs.items() if k.startswith("time_") and k.endswith("_s")}


def machine():
    cpu = [l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")]
    mem = [l.split()[1] for l in open("/proc/meminfo") if l.startswith("MemTotal")]
    return "%s × %d, %.0f GiB" % (cpu[0] if cpu else "?", len(cpu), int(mem[0]) / 2**20 if mem else 0)


rows = []
work = tempfile.mkdtemp(prefix="radnet-articulation-")
for case in CASES:
    text = open(case).read()
    name = os.path.splitext(os.path.basename(case))[0]
    folder = os.path.dirname(os.path.abspath(case))
    fixed_path = os.path.join(folder, ".%s-fixed.yaml" % name)  # beside the case: its includes resolve
    with open(fixed_path, "w") as f:
        f.write(without_articulation(text))
    try:
        fixed_wall, fixed = run(fixed_path, os.path.join(work, name + "-fixed.h5"))
    finally:
        os.remove(fixed_path)
    turned_wall, turned = run(case, os.path.join(work, name + ".h5"))
    nodes = fixed["nodes/name"].shape[0]
    configs = int(turned["report"].attrs["articulation_configurations"])
    rows.append((name, nodes, turned["orbit/time"].shape[0], configs,
                 int(turned["report"].attrs["eigendecompositions"]), int(turned["report"].attrs["articulation_recast_rows"]),
                 int(turned["report"].attrs["articulation_largest_update_rank"]), fixed_wall, turned_wall,
                 stages(fixed), stages(turned)))

reading = ""  # the hand-written reading below the tables survives a re-run
if os.path.exists(OUT):
    text = open(OUT).read()
    if "\n## Reading" in text:
        reading = text[text.index("\n## Reading"):]
with open(OUT, "w") as out:
    out.write("# Articulation benchmark (issue 34)\n\n")
    out.write("Written by `bench/bench_articulation.py` (`make bench`). Machine: %s. Default settings; whole "
              "process wall time of `radnet run`, the fixed run being the same file without `articulation:`.\n\n" % machine())
    out.write("| model | nodes | positions | configurations | eigendecompositions | rows recast | largest update rank "
              "| fixed, s | turning, s | ratio |\n|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        out.write("| %s | %d | %d | %d | %d | %d | %d | %.1f | %.1f | %.2f× |\n" % (r[0], r[1], r[2], r[3], r[4], r[5], r[6],
                                                                              r[7], r[8], r[8] / r[7]))
    out.write("\nStage times (s), fixed → turning:\n\n")
    for r in rows:
        keys = [k for k in r[10] if r[10][k] > 0.05 or r[9].get(k, 0) > 0.05]
        out.write("- %s: %s\n" % (r[0], ", ".join("%s %.2f → %.2f" % (k, r[9].get(k, 0.0), r[10][k]) for k in keys)))
    out.write(reading)
print(open(OUT).read())
