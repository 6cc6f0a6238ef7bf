#!/usr/bin/env python3
"""radnet on 1 and 2 MPI ranks, and the scaling model of docs/mpi.md (issue 15).

    bench_mpi.py RADNET OUT.md CASE.yaml [CASE.yaml ...]

Per case, three runs on this machine, in one session:
  A  one process, one thread              (the baseline)
  B  mpirun -np 2, one thread per rank    (MPI alone: A/B is its speed-up on 2 cores)
  C  one process, two threads             (what 2 cores give without MPI)
Wall times are measured around the command; stage times are /report's (under MPI the
slowest rank's). B's file is compared with A's bit for bit (tests/compare_h5.py).

From run A of the largest case it sets the model of docs/mpi.md: the shared-out stages
cost per ray (view factors) and per load ray (loads); the replicated stages (network,
eigendecomposition, exchange factors, band solves, uncertainty, output) grow as their
algorithms' powers of n (the power measured between the two largest cases is printed
beside), and the prediction for 50,000 nodes on 100 ranks is written with every
assumption it makes.
"""
import math
import os
import pathlib
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time

import h5py

RADNET = pathlib.Path(sys.argv[1]).resolve()
OUT = pathlib.Path(sys.argv[2])
CASES = [pathlib.Path(c).resolve() for c in sys.argv[3:]]
SOURCE = pathlib.Path(__file__).resolve().parent.parent
MPI_ENV = dict(os.environ, OMPI_MCA_btl_vader_single_copy_mechanism="none", OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
SHARED = ["view_factors", "environment_loads"]
# The stages every rank (or rank 0) does alone, and how their cost grows with n at a fixed
# view-factor density, rank k and position count: the sparse network and Lanczos's
# products with G have d n² entries; GR, its uncertainty and the written n × n matrices are
# dense; a band solve is n k per position.
REPLICATED = {"network": 2, "eigendecomposition": 2, "exchange_factors": 2, "band_solves": 1, "uncertainty": 2,
              "output": 2}


def run(label, case, work):
    d = work / label
    d.mkdir()
    out = d / "out.h5"
    if label == "B":
        cmd = ["mpirun", "-np", "2", str(RADNET), "run", str(case), "-o", str(out), "--threads", "1"]
    else:
        cmd = [str(RADNET), "run", str(case), "-o", str(out), "--threads", "1" if label == "A" else "2"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=MPI_ENV, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stderr}")
    with h5py.File(out, "r") as h5:
        r = h5["/report"].attrs
        stages = {k[5:-2]: float(v) for k, v in r.items() if k.startswith("time_") and k.endswith("_s")}
        # The file cannot hold the time spent writing it: radnet says it on stderr.
        written = re.search(r"radnet: wrote .* in ([0-9.eE+-]+) s", p.stderr)
        stages["output"] = float(written.group(1)) if written else 0.0
        info = {"rays": int(h5["/network"].attrs["rays_total"]), "nodes": h5["/nodes/name"].shape[0],
                "load_rays": int(r.get("planet_rays", 0)) + int(r.get("shadow_rays", 0)),
                "nnz": int((h5["/network/view_factors"][()] != 0).sum()) if h5["/network/view_factors"].size < 5e7
                else 0}
    return {"wall": wall, "stages": stages, "out": out, **info}


def identical(a, b):
    p = subprocess.run(["/usr/bin/python3", str(SOURCE / "tests/compare_h5.py"), str(a), str(b), "--quiet"],
                       capture_output=True, text=True)
    return p.returncode == 0


def machine():
    model = "unknown CPU"
    for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            model = line.split(":", 1)[1].strip()
            break
    mem = int(pathlib.Path("/proc/meminfo").read_text().split()[1]) / 2**20
    mpi = subprocess.run(["mpirun", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    return f"{model}, {os.cpu_count()} cores, {mem:.0f} GiB, {platform.platform()}, {mpi}"


def stage_table(results):
    names = []
    for r in results.values():
        for s in r["stages"]:
            if s not in names:
                names.append(s)
    rows = ["| stage | A: 1 process, 1 thread (s) | B: 2 ranks × 1 thread (s) | A/B | C: 1 process, 2 threads (s) |",
            "|---|---|---|---|---|"]
    for s in names + ["wall"]:
        a, b, c = (results[k]["wall"] if s == "wall" else results[k]["stages"].get(s, 0.0) for k in "ABC")
        ratio = f"{a / b:.2f}" if b > 0.01 else "–"
        label = "**whole run (wall clock)**" if s == "wall" else s
        rows.append(f"| {label} | {a:.2f} | {b:.2f} | {ratio} | {c:.2f} |")
    return rows


def fit_power(n1, t1, n2, t2):
    if t1 <= 0 or t2 <= 0 or n1 == n2:
        return 2.0
    return math.log(t2 / t1) / math.log(n2 / n1)


def model(all_results):
    """The prediction for 50,000 nodes on 100 ranks from run A of the two largest cases."""
    (n1, r1), (n2, r2) = sorted(((r["A"]["nodes"], r["A"]) for r in all_results.values()), key=lambda x: x[0])[-2:]
    per_ray = r2["stages"].get("view_factors", 0) / max(r2["rays"], 1)
    per_load_ray = r2["stages"].get("environment_loads", 0) / max(r2["load_rays"], 1)
    rays_per_node = r2["rays"] / n2
    load_rays_per_node = r2["load_rays"] / n2
    N, R = 50000, 100
    lines = [f"Fitted from run A (one core) of the {n1}- and {n2}-node cases:", "",
             f"- view factors: {per_ray * 1e9:.0f} ns per ray ({rays_per_node:.0f} rays per node);",
             f"- loads: {per_load_ray * 1e9:.0f} ns per planet or shadow ray ({load_rays_per_node:.0f} per node "
             f"over the sweep);"]
    shared_s = N * (rays_per_node * per_ray + load_rays_per_node * per_load_ray) / R
    replicated_s = 0.0
    for s, p in REPLICATED.items():
        t1, t2 = r1["stages"].get(s, 0.0), r2["stages"].get(s, 0.0)
        if t2 <= 0:
            continue
        t = t2 * (N / n2) ** p
        replicated_s += t
        lines.append(f"- {s}: {t2:.2f} s at {n2} nodes; grows as n^{p} (its algorithm's power; measured n^"
                     f"{fit_power(n1, t1, n2, t2):.2f} from {n1} to {n2} nodes, where fixed costs still weigh) → {t:.0f} s at {N} nodes, on every rank or rank 0;")
    density = r2["nnz"] / n2**2 if r2["nnz"] else 0.04
    gather_bytes = density * N * N * 2 * 24  # F and σ(F), (row, column, value) each
    gather_s = gather_bytes / 5e9 * math.log2(R)
    lines += ["",
              f"For N = {N} nodes on R = {R} ranks (same rays per node, F as dense as here: "
              f"{100 * density:.1f} % non-zero):", "",
              f"- shared-out ray casting: {shared_s:.0f} s (one core per rank);",
              f"- joining F and σ(F) ({gather_bytes / 1e9:.1f} GB of triplets) by {R} broadcasts at an assumed "
              f"5 GB/s per link, log₂ R deep: {gather_s:.0f} s;",
              f"- replicated stages: {replicated_s:.0f} s on one core (less with threads inside the rank);",
              f"- **predicted: {shared_s + gather_s + replicated_s:.0f} s**, against "
              f"{N * (rays_per_node * per_ray + load_rays_per_node * per_load_ray) + replicated_s:.0f} s on one core.",
              ""]
    return lines


def main():
    all_results = {}
    lines = ["# radnet on MPI ranks: measured 1 → 2 ranks, and the scaling model", "",
             f"Written by `bench/bench_mpi.py` (in `make bench`). Machine: {machine()}.", "",
             "Three runs per case, one after the other in one session: **A** one process on one thread "
             "(`--threads 1`), **B** `mpirun -np 2` with one thread per rank, **C** one process on two threads. "
             "A/B is what MPI alone gives on 2 cores; B against C is what it costs beside threads. Stage times "
             "are `/report`'s (under MPI the slowest rank's). Every B file is compared with A's bit for bit.", ""]
    with tempfile.TemporaryDirectory() as tmp:
        for case in CASES:
            work = pathlib.Path(tmp) / case.stem
            work.mkdir()
            results = {label: run(label, case, work) for label in "ABC"}
            all_results[case.stem] = results
            same = identical(results["A"]["out"], results["B"]["out"])
            lines += [f"## {case.stem} ({results['A']['nodes']} nodes, {results['A']['rays']} view-factor rays, "
                      f"{results['A']['load_rays']} load rays)", "",
                      f"2-rank file {'bit-identical to' if same else 'DIFFERENT from'} the one-process file.", ""]
            lines += stage_table(results) + [""]
            print(f"{case.stem}: A {results['A']['wall']:.1f} s, B {results['B']['wall']:.1f} s, "
                  f"C {results['C']['wall']:.1f} s, identical: {same}", flush=True)
    lines += ["## The model: 50,000 nodes on 100 ranks", ""] + model(all_results)
    lines += ["What it leaves out, plainly: the replicated stages are the Amdahl limit (rank 0 decomposes G "
              "while the others wait; every rank forms the dense exchange factors and solves its bands), and "
              "every rank holds the dense n × n matrices of docs/limits.md (GR alone is 20 GB at 50,000 nodes), "
              "so such a run needs one rank per large-memory node. The link speed is an assumption, not a "
              "measurement: this machine has one node.", ""]
    OUT.write_text("\n".join(lines))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
