#!/usr/bin/env python3
"""radnet under mpirun (issue 15, docs/mpi.md).

    check_mpi.py RADNET SOURCE_DIR WORK_DIR

1. Cases run with `mpirun -np 2` (and 3) give the single-process file bit for bit
   (tests/compare_h5.py; timings and /report mpi_ranks excepted): every random stream is
   keyed by node, replica or sample, and the ranks' parts are joined bit for bit. The
   CubeSat (view-factor rows and orbit loads shared out), the hot/cold CubeSat (design
   cases and optical samples) and an analytic enclosure.
2. `radnet check` under mpirun passes and prints its verdict once.
3. Failures: a bad mesh seen only by rank 1 (before any collective, while rank 0 is in
   the run) and an output rank 0 cannot write (after every collective): every rank exits
   with the same code (2, 4), the bad mesh located at file:line:column, nothing left
   behind, no hang.
"""
import os
import pathlib
import shutil
import subprocess
import sys

RADNET, SOURCE, WORK = (pathlib.Path(a).resolve() for a in sys.argv[1:4])
MPIRUN = shutil.which("mpirun")
# Root in CI, 2 cores: both allowed. Shared memory without the single-copy mechanism,
# which containers' ptrace rules refuse.
MPI_ENV = dict(os.environ, OMPI_MCA_btl_vader_single_copy_mechanism="none", OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               # The sanitizer build: Open MPI keeps allocations past MPI_Finalize, which
               # LeakSanitizer would report as radnet's.
               ASAN_OPTIONS=os.environ.get("ASAN_OPTIONS", "") + ":detect_leaks=0")
TIMEOUT_S = 600  # a hang fails the test instead of stalling ctest
failures = []


def mpirun(args, ranks=2, env=None):
    return subprocess.run([MPIRUN, "-np", str(ranks), *map(str, args)], env=env or MPI_ENV, capture_output=True,
                          text=True, timeout=TIMEOUT_S)


def same_result(case, ranks=2):
    """One process and `ranks` ranks: the same file, bit for bit."""
    name = f"{pathlib.Path(case).stem}-{ranks}"
    files = {}
    for label, prefix in (("single", []), ("mpi", None)):
        d = WORK / name / label
        d.mkdir(parents=True)
        out = d / "out.h5"  # the same name: it is part of the result (/xdmf/series_file)
        args = ["run", case, "-o", out, "-q"]
        if prefix is None:
            p = mpirun([RADNET, *args], ranks)
        else:
            p = subprocess.run([RADNET, *args], capture_output=True, text=True, timeout=TIMEOUT_S)
        if p.returncode != 0:
            failures.append(f"{name} ({label}) exited {p.returncode}:\n{p.stderr[-2000:]}")
            return
        files[label] = out
    import h5py
    with h5py.File(files["mpi"], "r") as h5:
        ranks_written = h5["/report"].attrs["mpi_ranks"]
    if int(ranks_written) != ranks:
        failures.append(f"{name}: /report mpi_ranks is {ranks_written}, not {ranks}")
    cmp = subprocess.run(["/usr/bin/python3", SOURCE / "tests/compare_h5.py", files["single"], files["mpi"]],
                         capture_output=True, text=True)
    if cmp.returncode != 0:
        failures.append(f"{name}: the {ranks}-rank result differs from one process:\n{cmp.stdout[-3000:]}{cmp.stderr}")
    else:
        print(f"{name}: {ranks} ranks bit-identical to one process")


# A case of 10,400 nodes (past kSharedRowsMinNodes): its rows of F, σ_F, G and GR are shared
# out over the ranks (docs/mpi.md, "Rows shared out"). Few rays and positions: a quick run.
SHARED_CASE = """name: shared-rows
materials:
  mli: {emissivity: 0.05, absorptivity: 0.1}
  radiator: {emissivity: 0.85, absorptivity: 0.2}
geometry:
  - rectangle: {name: px, origin: [0.5, -0.5, -0.5], u: [0, 1, 0], v: [0, 0, 1], front: mli, nodes: [50, 50]}
  - rectangle: {name: mx, origin: [-0.5, -0.5, -0.5], u: [0, 0, 1], v: [0, 1, 0], front: mli, nodes: [50, 50]}
  - rectangle: {name: py, origin: [-0.5, 0.5, -0.5], u: [0, 0, 1], v: [1, 0, 0], front: radiator, nodes: [50, 50]}
  - rectangle: {name: my, origin: [-0.5, -0.5, -0.5], u: [1, 0, 0], v: [0, 0, 1], front: radiator, nodes: [50, 50]}
  - rectangle: {name: wing, origin: [0.55, -0.5, -0.5], u: [0, 1, 0], v: [1.0, 0, 0], front: radiator,
                back: mli, nodes: [20, 10]}
orbit: {altitude: 500.0e3, sun_synchronous: true, ltan: 10.5, epoch: 2026-06-21T00:00:00Z, positions: 8}
attitude: {mode: nadir}
solver:
  accuracy: 0.05
  view_factors: {method: monte_carlo, rays: 200, seed: 3}
"""


def shared_rows():
    """Rows shared out: 2 and 3 ranks bit for bit; against one process, the same datasets
    to 1e-7 of each one's largest value: the correction's multipliers are solved by another
    method (to 1e-13 of the residual; F and G then agree to 1e-16), and the band solves'
    refinement, started from pairs of equal |λ| in another order, stops elsewhere within its
    tolerance (measured: 1.1e-10). Eigenvalues compared sorted, eigenvectors left out."""
    d = WORK / "shared-rows"
    d.mkdir(parents=True)
    case = d / "shared.yaml"
    case.write_text(SHARED_CASE)
    files = {}
    for label, ranks in (("single", 1), ("two", 2), ("three", 3)):
        (d / label).mkdir()
        out = d / label / "out.h5"
        args = [RADNET, "run", case, "-o", out, "-q", "--threads", "1"]
        p = subprocess.run(list(map(str, args)), capture_output=True, text=True, timeout=TIMEOUT_S) if ranks == 1 \
            else mpirun(args, ranks)
        if p.returncode != 0:
            failures.append(f"shared rows ({label}) exited {p.returncode}:\n{p.stderr[-2000:]}")
            return
        files[label] = out
    cmp = subprocess.run(["/usr/bin/python3", SOURCE / "tests/compare_h5.py", files["two"], files["three"]],
                         capture_output=True, text=True)
    if cmp.returncode != 0:
        failures.append(f"shared rows: 3 ranks differ from 2:\n{cmp.stdout[-3000:]}{cmp.stderr}")
    import h5py
    import numpy as np
    with h5py.File(files["single"], "r") as a, h5py.File(files["two"], "r") as b:
        names = {}
        for f, key in ((a, "a"), (b, "b")):
            f.visititems(lambda name, obj, key=key: names.setdefault(name, set()).add(key)
                         if isinstance(obj, h5py.Dataset) else None)
        one_sided = sorted(n for n, keys in names.items() if len(keys) == 1)
        if one_sided:
            failures.append(f"shared rows: datasets in one file only: {one_sided[:10]}")
        worst = (0.0, "")
        for name in sorted(n for n, keys in names.items() if len(keys) == 2):
            x, y = np.asarray(a[name][()]), np.asarray(b[name][()])
            if x.dtype.kind not in "fi" or x.shape != y.shape or x.size == 0:
                continue
            if name.endswith("vectors") or name.endswith("basis") or name.endswith("core"):
                continue
            if name == "eigen/values":
                x, y = np.sort(x), np.sort(y)
            scale = max(float(np.max(np.abs(x))), 1e-300)
            worst = max(worst, (float(np.max(np.abs(x.astype(float) - y.astype(float)))) / scale, name))
        if worst[0] > 1e-7:
            failures.append(f"shared rows: one process against 2 ranks: {worst[1]} off by {worst[0]:.3g} of its largest")
        elif not one_sided and cmp.returncode == 0:
            print(f"shared rows: 2 and 3 ranks bit for bit; one process to {worst[0]:.2g} ({worst[1]})")
    # Rank 0 cannot write (a design case's ParaView sidecar's name is a directory, found only
    # as the files are committed) after the ranks have joined the matrices' blocks: every
    # rank exits 4, nothing left behind.
    u = WORK / "shared-unwritable"
    (u / "out.hot.xmf").mkdir(parents=True)
    two_cases = u / "shared-cases.yaml"
    two_cases.write_text(SHARED_CASE.replace(
        "attitude: {mode: nadir}\n", "attitude: {mode: nadir}\ncases:\n  hot: {environment: {solar_constant: 1414}}\n"
        "  cold: {environment: {solar_constant: 1322}}\n"))
    p, codes = per_rank_run("shared-unwritable", [two_cases, two_cases], u / "out.h5")
    left = [f.name for f in u.iterdir() if f.name.startswith("out.h5")]
    if codes != [("rank-0.rc", "4"), ("rank-1.rc", "4")] or left:
        failures.append(f"shared rows, unwritable output: mpirun exit {p.returncode}, ranks {codes}, left {left}, "
                        f"stderr:\n{p.stderr[-2000:]}")


def check_command():
    case = SOURCE / "cases/analytic/perpendicular-squares.yaml"
    p = mpirun([RADNET, "check", case])
    if p.returncode != 0 or p.stdout.count("all checks passed") != 1:
        failures.append(f"radnet check under mpirun: exit {p.returncode}, stdout:\n{p.stdout}\nstderr:\n{p.stderr}")
    else:
        print("radnet check under mpirun: passed, verdict printed once")


def per_rank_run(name, cases, out, every_rank=True):
    """Rank r runs cases[r] (the wrapper records each rank's exit code). every_rank: mpirun
    lets every rank finish (by default it kills the others as soon as one exits non-zero,
    before they record their codes, and then exits with that first code itself)."""
    d = WORK / name
    d.mkdir(parents=True, exist_ok=True)
    wrapper = d / "rank.sh"
    wrapper.write_text(
        "#!/bin/sh\n"
        f'if [ "$OMPI_COMM_WORLD_RANK" = 1 ]; then c="{cases[1]}"; else c="{cases[0]}"; fi\n'
        f'"{RADNET}" run "$c" -o "{out}" -q\n'
        f'rc=$?; echo $rc > "{d}/rank-$OMPI_COMM_WORLD_RANK.rc"; exit $rc\n')
    wrapper.chmod(0o755)
    p = mpirun([wrapper], env=dict(MPI_ENV, OMPI_MCA_orte_abort_on_non_zero_status="0") if every_rank else None)
    codes = sorted((f.name, f.read_text().strip()) for f in d.glob("rank-*.rc"))
    return p, codes


def failing_ranks():
    good = SOURCE / "cases/examples/cubesat-3u.yaml"
    d = WORK / "bad-mesh"
    d.mkdir(parents=True)
    # The same case, but its mesh, on rank 1 only, has a face with a corner index out of range.
    mesh = d / "panel.off"
    mesh.write_text("OFF\n4 2 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n3 0 1 2\n3 0 2 9\n")
    bad = d / "bad.yaml"
    bad.write_text((SOURCE / "cases/examples/cubesat-3u.yaml").read_text().replace(
        "geometry:", f"geometry:\n  - mesh: {{name: bad_panel, file: {mesh}, scale: 1.0, front: solar_cell}}", 1))
    out = d / "out.h5"
    p, codes = per_rank_run("bad-mesh", [good, bad], out)
    located = f"{mesh}:8:" in p.stderr or f"{bad}:" in p.stderr
    if codes != [("rank-0.rc", "2"), ("rank-1.rc", "2")] or not located:
        failures.append(f"bad mesh on rank 1: mpirun exit {p.returncode}, ranks {codes}, stderr:\n{p.stderr[-2000:]}")
    elif out.exists() or list(d.glob("out.h5*")):
        failures.append(f"bad mesh on rank 1 left {list(d.glob('out.h5*'))}")
    else:
        print("bad mesh on rank 1: exit 2 on both ranks, located, nothing written")
    # What the user sees with mpirun's defaults: its own exit code, 2.
    p, _ = per_rank_run("bad-mesh-default", [good, bad], WORK / "bad-mesh-default" / "out.h5", every_rank=False)
    if p.returncode != 2:
        failures.append(f"bad mesh on rank 1, mpirun's defaults: mpirun exit {p.returncode}, not 2")
    # Ranks that read different cases (here a seed changed on rank 1's copy) refuse to run:
    # their shares would join into a plausible-looking mix.
    d = WORK / "different"
    d.mkdir(parents=True)
    other = d / "cubesat-3u.yaml"
    other.write_text(good.read_text().replace("seed: 1}", "seed: 2}", 1))
    p, codes = per_rank_run("different", [good, other], d / "out.h5")
    if codes != [("rank-0.rc", "2"), ("rank-1.rc", "2")] or "read a different case" not in p.stderr:
        failures.append(f"different cases: mpirun exit {p.returncode}, ranks {codes}, stderr:\n{p.stderr[-2000:]}")
    else:
        print("ranks that read different cases: exit 2 on both, said")
    # Rank 0 fails after every collective: the hot case's ParaView sidecar's name is taken
    # by a directory, found only when the files are written; rank 1 waits in the last agreement.
    d = WORK / "unwritable"
    (d / "out.hot.xmf").mkdir(parents=True)
    hot_cold = SOURCE / "cases/examples/cubesat-hot-cold.yaml"
    p, codes = per_rank_run("unwritable", [hot_cold, hot_cold], d / "out.h5")
    left = [f.name for f in d.iterdir() if f.name.startswith("out.h5")]
    if codes != [("rank-0.rc", "4"), ("rank-1.rc", "4")] or left:
        failures.append(f"unwritable output: mpirun exit {p.returncode}, ranks {codes}, left {left}, stderr:\n"
                        f"{p.stderr[-2000:]}")
    else:
        print("output rank 0 cannot write: exit 4 on both ranks, nothing left")


def main():
    if MPIRUN is None:
        print("mpirun not found (make deps installs openmpi-bin)")
        return 1
    shutil.rmtree(WORK, ignore_errors=True)
    WORK.mkdir(parents=True)
    same_result(SOURCE / "cases/examples/cubesat-3u.yaml")
    same_result(SOURCE / "cases/examples/cubesat-hot-cold.yaml")
    same_result(SOURCE / "cases/analytic/perpendicular-squares.yaml")
    # Sun-pointing: the planet loads from the sky kernel, its nodes shared out over 3 ranks.
    sun = WORK / "cubesat-sun-pointing.yaml"
    sun.write_text((SOURCE / "cases/examples/cubesat-3u.yaml").read_text().replace(
        "attitude: {mode: nadir}", "attitude: {mode: sun}"))
    same_result(sun, ranks=3)
    # Sun-tracking wings: every configuration's rows, loads and GR on every rank alike.
    same_result(SOURCE / "cases/examples/tracking-wings.yaml")
    # The same spinning: the planet moves in the body frame, so each configuration's turning
    # rows take a sky kernel of their own (10 configurations), their nodes shared out.
    spin = WORK / "tracking-wings-spin.yaml"
    spin.write_text((SOURCE / "cases/examples/tracking-wings.yaml").read_text().replace(
        "attitude: {mode: nadir}", "attitude: {mode: spin, quaternion: [1, 0, 0, 0], spin_axis: [0, 0, 1], spin_rate: 0.3}"))
    same_result(spin)
    # Three ranks for two design cases: one rank solves none; 64 samples split unevenly.
    same_result(SOURCE / "cases/examples/cubesat-hot-cold.yaml", ranks=3)
    shared_rows()
    check_command()
    failing_ranks()
    for f in failures:
        print("FAIL:", f)
    if not failures:
        shutil.rmtree(WORK, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
