#!/usr/bin/python3
"""Peak memory per MPI rank with the network's rows shared out (docs/mpi.md, "Rows shared
out"): a case run as one process and under `mpirun -np R`, each process's resident set
sampled every 0.5 s and keyed by the progress line it was in, so the table says which stage
set each peak. Writes a markdown report.

usage: bench_mpi_memory.py RADNET OUT.md CASE.yaml [--ranks 2] [--defaults]

--defaults: the case without its `solver:` block (bench_scale.defaults_copy), as a user
runs it. Each process runs on one thread (--threads 1), so R ranks use R cores.
"""
import os
import platform
import re
import subprocess
import sys
import tempfile
import threading
import time

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_scale  # noqa: E402

MPI_ENV = dict(os.environ, OMPI_MCA_btl_vader_single_copy_mechanism="none", OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def rank_processes(binary):
    """{pid: rank} of the processes running `binary` (rank from Open MPI's environment)."""
    out = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            if open(f"/proc/{d}/cmdline").read().split("\0")[0] != binary:
                continue
            env = open(f"/proc/{d}/environ").read().split("\0")
            rank = [e.split("=", 1)[1] for e in env if e.startswith("OMPI_COMM_WORLD_RANK=")]
            out[d] = int(rank[0]) if rank else 0
        except (OSError, ValueError):
            pass
    return out


def run(radnet, case, ranks):
    """Wall time, {rank: peak bytes}, {stage line: {rank: bytes}} and the output's nnz(F), k."""
    out = tempfile.mktemp(suffix=".h5")
    args = [radnet, "run", case, "-o", out, "--threads", "1"]
    if ranks > 1:
        args = ["mpirun", "-np", str(ranks), *args]
    t0 = time.monotonic()
    p = subprocess.Popen(args, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True, env=MPI_ENV)
    stage = ["start"]
    peaks = {}

    def sample():
        while p.poll() is None:
            for pid, rank in rank_processes(radnet).items():
                try:
                    for line in open(f"/proc/{pid}/status"):
                        if line.startswith("VmRSS"):
                            key = (stage[0], rank)
                            peaks[key] = max(peaks.get(key, 0), int(line.split()[1]) * 1024)
                except OSError:
                    pass
            time.sleep(0.5)

    sampler = threading.Thread(target=sample)
    sampler.start()
    for line in p.stderr:
        if line.startswith("radnet: "):  # a progress bar's lines are one stage: "view factors (rays)"
            stage[0] = re.sub(r"\s*\d+ %.*", "", line.strip()[8:])[:72]
    p.wait()
    sampler.join()
    wall = time.monotonic() - t0
    if p.returncode != 0:
        raise SystemExit(f"{case} on {ranks} rank(s): exit {p.returncode}")
    with h5py.File(out) as h5:
        nnz = h5["/network/sparse/view_factors/data"].shape[0]
        nnz_raw = h5["/network/sparse/view_factors_raw/data"].shape[0]
        n = h5["/nodes/name"].shape[0]
        k = int(h5["/eigen"].attrs["rank"])
        times = {key[5:-2]: float(v) for key, v in h5["/report"].attrs.items()
                 if key.startswith("time_") and key.endswith("_s") and not key.endswith("predicted_s")}
    for f in (out, out[:-3] + ".xmf"):
        if os.path.exists(f):
            os.unlink(f)
    per_rank = {}
    by_stage = {}
    for (s, r), b in peaks.items():
        per_rank[r] = max(per_rank.get(r, 0), b)
        by_stage.setdefault(s, {})[r] = b
    return {"wall": wall, "per_rank": per_rank, "by_stage": by_stage, "n": n, "nnz": nnz, "nnz_raw": nnz_raw, "k": k,
            "times": times}


def main():
    args = sys.argv[1:]
    if len(args) < 3:
        raise SystemExit(__doc__)
    radnet, report, case = os.path.abspath(args[0]), args[1], args[2]
    ranks = int(args[args.index("--ranks") + 1]) if "--ranks" in args else 2
    copy = bench_scale.defaults_copy(case) if "--defaults" in args else None
    try:
        one = run(radnet, copy or case, 1)
        many = run(radnet, copy or case, ranks)
    finally:
        if copy:
            os.unlink(copy)
    gb = 1e9
    lines = [
        "# Memory per MPI rank, rows shared out",
        "",
        f"Written by `bench/bench_mpi_memory.py` ({time.strftime('%Y-%m-%d')}). Machine: {bench_scale.machine()}, "
        f"Python {platform.python_version()}. Case: `{os.path.relpath(case)}`"
        f"{' at the defaults (its solver block removed)' if copy else ''}; every process on one thread. Resident set "
        "sampled every 0.5 s.",
        "",
        f"n = {one['n']}, nnz(F) = {one['nnz']} (raw estimate {one['nnz_raw']}), k = {one['k']}.",
        "",
        "| run | wall (s) | peak per process (GB) | of the one-process peak |",
        "|---|---|---|---|",
    ]
    base = max(one["per_rank"].values())
    lines.append(f"| 1 process | {one['wall']:.0f} | {base / gb:.2f} | 100 % |")
    for r in sorted(many["per_rank"]):
        lines.append(f"| {ranks} ranks: rank {r} | {many['wall']:.0f} | {many['per_rank'][r] / gb:.2f} | "
                     f"{100 * many['per_rank'][r] / base:.0f} % |")
    lines += ["", f"Peak by stage (the progress line the run was in; GB; one process, then rank 0 … {ranks - 1}):", "",
              "| stage | 1 process | " + " | ".join(f"rank {r}" for r in range(ranks)) + " |",
              "|---|---|" + "---|" * ranks]
    stages = list(one["by_stage"])
    for s in many["by_stage"]:
        if s not in stages:
            stages.append(s)
    for s in stages:
        a = one["by_stage"].get(s, {})
        b = many["by_stage"].get(s, {})
        lines.append(f"| {s} | {a.get(0, 0) / gb:.2f} | " +
                     " | ".join(f"{b.get(r, 0) / gb:.2f}" for r in range(ranks)) + " |")
    lines += ["", "Stage times (s; /report's, under MPI the slowest rank's):", "",
              f"| stage | 1 process | {ranks} ranks |", "|---|---|---|"]
    for key in one["times"]:
        lines.append(f"| {key} | {one['times'][key]:.1f} | {many['times'].get(key, float('nan')):.1f} |")
    with open(report, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
