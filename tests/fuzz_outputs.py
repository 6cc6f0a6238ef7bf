#!/usr/bin/python3
"""Hostile families for what radnet writes and reads back (issue 38), seeded and deterministic:

  results  malformed results given to `export` (every format) and `report`: datasets reshaped,
           retyped, deleted, filled with NaN/Inf or out-of-range indices, files cut short or with
           bytes flipped. Exit 0, 2 or 4 only, never a signal or a Python traceback, something
           said on stderr when not 0, no output left on failure, no NaN/Inf written on success.
  files    filesystem tricks: planted symlinks at the output and its temporaries, names over
           255 bytes, a file used as a folder, and (as root) full and read-only tmpfs mounts
           of random sizes. Exit 2 or 4, the victim and the old output unchanged, nothing left.
  imports  malformed ESATAN TMD files (the real DISCTR one, mutated as the results are) imported
           by a case: exit 0, 2 or 3 only, never a signal or a traceback, no output on failure.
  signals  catchable signals at random instants of a run over an old result and sidecar: the
           old pair or the new pair stays, never a mix and never a temporary.

Usage: fuzz_outputs.py RADNET SOURCE_DIR WORK_DIR [--seed N] [--results N] [--reports N] [--signals N] [--imports N]
Prints one line per problem and a summary; exit 1 when any contract was broken.
"""
import argparse
import hashlib
import os
import pathlib
import random
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

CASE = "cases/examples/cubesat-3u.yaml"  # geometry, orbit, heaters, lumped nodes: every group
FORMATS = {"esatan": "deck.d", "sinda": "deck.sin", "csv": "deck-csv", "tmd": "deck.TMD"}
TMD = "tests/data/esatan/DISCTR_TRANSIENT.TMD"  # a real ESATAN results file, for the imports family


def run(cmd, cwd, timeout=120):
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, errors="replace")
    return p.returncode, p.stdout, p.stderr


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None


def temporaries(folder):
    return [p.name for p in folder.rglob("*") if ".tmp-" in p.name or p.name.startswith(".radnet-")]


def contract(rc, out, err, allowed=(0, 2, 4)):
    """The exit-code contract of a command that reads or writes files."""
    problems = []
    if rc < 0:
        problems.append(f"killed by signal {-rc}")
    elif rc not in allowed:
        problems.append(f"exit {rc}")
    if "Traceback" in out or "Traceback" in err:
        problems.append("a Python traceback reached the user")
    if rc != 0 and not err.strip():
        problems.append(f"exit {rc} with nothing on stderr")
    return problems


# ---- results -------------------------------------------------------------------------------

def datasets(path):
    names = []
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
    return sorted(names)


def mutate_dataset(rng, f, name):
    d = f[name]
    data, attrs = d[()], dict(d.attrs)
    op = rng.choice(["reshape", "nonfinite", "index", "delete", "string", "scalar", "empty"])
    if op == "nonfinite" and not (isinstance(data, np.ndarray) and data.dtype.kind == "f" and data.size):
        op = "reshape"
    if op == "index" and not (isinstance(data, np.ndarray) and data.dtype.kind in "iu" and data.size):
        op = "delete"
    if op == "reshape" and not (isinstance(data, np.ndarray) and data.ndim >= 1 and data.size):
        op = "scalar"
    del f[name]
    if op == "delete":
        return op
    if op == "reshape":  # a row too few or too many, or the axes swapped
        how = rng.choice(["short", "long", "swap"])
        if how == "short" and data.shape[0] > 1:
            data = data[:-1]
        elif how == "swap" and data.ndim == 2:
            data = data.T.copy()
        else:
            data = np.concatenate([data, data[:1]]) if data.dtype.kind != "O" else np.concatenate([data, data[:1]])
    elif op == "nonfinite":
        flat = data.reshape(-1).copy()
        flat[rng.randrange(flat.size)] = rng.choice([np.nan, np.inf, -np.inf, 1e308])
        data = flat.reshape(data.shape)
    elif op == "index":
        flat = data.reshape(-1).copy()
        flat[rng.randrange(flat.size)] = rng.choice([1000, -5, 2**31 - 1, -(2**31)])
        data = flat.reshape(data.shape)
    elif op == "string":
        data = np.array([b"not a number"] * max(1, getattr(data, "size", 1)), dtype=h5py.string_dtype())
    elif op == "scalar":
        data = np.float64(rng.choice([0.0, np.nan, 1e300]))
    elif op == "empty":
        data = np.zeros((0,), dtype=getattr(data, "dtype", np.float64))
    f.create_dataset(name, data=data)
    for k, v in attrs.items():
        f[name].attrs[k] = v
    return op


def malformed_result(rng, base, target, names):
    shutil.copy(base, target)
    kind = rng.random()
    if kind < 0.8:  # through HDF5: one or two datasets broken
        with h5py.File(target, "r+") as f:
            # Mostly the groups export and report read; now and then any dataset at all.
            read = [n for n in names if n.split("/")[0] in ("nodes", "network", "thermal", "loads", "solution",
                                                              "cases", "heaters", "orbit", "eigen")]
            pool = read if rng.random() < 0.85 and read else names
            ops = [f"{n}:{mutate_dataset(rng, f, n)}" for n in rng.sample(pool, rng.choice([1, 1, 2]))]
        return ",".join(ops)
    data = bytearray(target.read_bytes())
    if kind < 0.9:
        cut = rng.randrange(len(data))
        target.write_bytes(bytes(data[:cut]))
        return f"cut at {cut} bytes"
    for _ in range(rng.choice([1, 8, 64])):
        data[rng.randrange(len(data))] = rng.randrange(256)
    target.write_bytes(bytes(data))
    return "bytes flipped"


def produced_nonfinite(path):
    files = [path] if path.is_file() else list(path.rglob("*")) if path.is_dir() else []
    pattern = re.compile(rb"(?<![A-Za-z_])(nan|inf|infinity)(?![A-Za-z_])", re.I)
    return [str(p) for p in files if p.is_file() and p.suffix != ".png" and pattern.search(p.read_bytes())]


def family_results(args, rng, base, problems):
    names = datasets(base)
    folder = args.work / "results"
    count = 0
    for i in range(args.results + args.reports):
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        what = malformed_result(rng, base, folder / "r.h5", names)
        if i < args.results:
            fmt = rng.choice(sorted(FORMATS))
            cmd = [str(args.radnet), "export", "r.h5", "--format", fmt, "-o", FORMATS[fmt]]
            output = folder / FORMATS[fmt]
        else:
            cmd = [str(args.radnet), "report", "r.h5", "-o", "rep"]
            output = folder / "rep"
        rc, out, err = run(cmd, folder)
        args.tally[rc] = args.tally.get(rc, 0) + 1
        found = contract(rc, out, err)
        if rc != 0 and output.exists():
            found.append(f"exit {rc} but {output.name} was written")
        if rc == 0:
            found += [f"NaN/Inf written into {p}" for p in produced_nonfinite(output)]
        found += [f"left {t}" for t in temporaries(folder)]
        if found:  # kept for a rerun by hand
            (args.work / "failures").mkdir(exist_ok=True)
            shutil.copy(folder / "r.h5", args.work / "failures" / f"results-{i}.h5")
        for p in found:
            problems.append(f"results #{i} ({' '.join(cmd[1:3])}; {what}): {p}: {err.strip()[-200:]}")
        count += 1
    return count


# ---- imports -------------------------------------------------------------------------------

def family_imports(args, rng, problems):
    source = args.source / TMD
    if not source.is_file():
        return 0
    names = datasets(source)
    folder = args.work / "imports"
    for i in range(args.imports):
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        what = malformed_result(rng, source, folder / "m.TMD", names)
        (folder / "m.TMD").chmod(0o644)
        (folder / "imp.yaml").write_text("name: imp\nimport: {esatan_tmd: m.TMD}\n")
        cmd = [str(args.radnet), "run", "imp.yaml", "-o", "out.h5", "-q"]
        rc, out, err = run(cmd, folder)
        found = contract(rc, out, err, allowed=(0, 2, 3))
        if rc != 0 and (folder / "out.h5").exists():
            found.append(f"exit {rc} but out.h5 was written")
        found += [f"left {t}" for t in temporaries(folder)]
        if found:
            (args.work / "failures").mkdir(exist_ok=True)
            shutil.copy(folder / "m.TMD", args.work / "failures" / f"imports-{i}.TMD")
        for p in found:
            problems.append(f"imports #{i} ({what}): {p}: {err.strip()[-200:]}")
    return args.imports


# ---- files ---------------------------------------------------------------------------------

def mount_tmpfs(path, size_kib, readonly=False):
    path.mkdir(parents=True, exist_ok=True)
    opts = f"size={size_kib}k" + (",ro" if readonly else "")
    return subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", str(path)], capture_output=True).returncode == 0


def unmount(path):
    subprocess.run(["umount", str(path)], capture_output=True)


def one_file_trick(args, rng, base, case, folder, trick):
    """(command, the files that must stay unchanged {path: digest}, allowed exit codes)."""
    radnet = str(args.radnet)
    victim = folder / "victim.txt"
    victim.write_text("precious\n")
    command = rng.choice(["run", "export", "report"])
    target = {"run": "out.h5", "export": "out.d", "report": "rep"}[command]
    prefix = {"run": [radnet, "run", str(case)], "export": [radnet, "export", str(base), "--format", "esatan"],
              "report": [radnet, "report", str(base)]}[command]
    if trick == "symlink-output":
        # Replacing the link itself (as mv does) or refusing are both fine; writing through it is not.
        (folder / target).symlink_to(victim)
        return prefix + ["-o", target], (0, 2, 4)
    if trick == "symlink-temporaries":
        # The next few hundred pids' temporaries planted as links to the victim.
        try:
            last = int(pathlib.Path("/proc/sys/kernel/ns_last_pid").read_text())
        except (OSError, ValueError):  # not readable in every container: our own pid is near
            last = os.getpid()
        for pid in range(last + 1, last + 400):
            for name in (f"out.h5.tmp-{pid}", f"out.xmf.tmp-{pid}", f"out.d.tmp-{pid}"):
                (folder / name).symlink_to(victim)
        return prefix + ["-o", target], (0,)
    if trick == "long-name":
        return prefix + ["-o", "x" * rng.choice([256, 300, 1000]) + ".h5"], (2, 4)
    if trick == "file-as-folder":
        return prefix + ["-o", "victim.txt/" + target], (2, 4)
    raise ValueError(trick)


def family_files(args, rng, base, case, problems):
    tricks = ["symlink-output", "symlink-temporaries", "long-name", "file-as-folder"]
    folder = args.work / "files"
    count = 0
    for i, trick in enumerate(tricks * 3):
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        cmd, allowed = one_file_trick(args, rng, base, case, folder, trick)
        before = digest(folder / "victim.txt")
        rc, out, err = run(cmd, folder)
        found = contract(rc, out, err, tuple(sorted(set(allowed) | {2, 4})) if trick == "symlink-temporaries" else allowed)
        if digest(folder / "victim.txt") != before:
            found.append("the victim file was changed")
        found += [f"left {t}" for t in temporaries(folder) if not (folder / t).is_symlink()]
        for p in found:
            problems.append(f"files #{i} ({trick}, {cmd[1]}): {p}: {err.strip()[-200:]}")
        count += 1
    if os.geteuid() != 0:
        print("fuzz_outputs: not root: the full and read-only tmpfs tricks are skipped")
        return count
    for i in range(16):
        mount = args.work / "mnt"
        readonly = i % 4 == 3
        size = rng.choice([4, 16, 64, 256, 1024])
        if not mount_tmpfs(mount, size, readonly=False):
            print("fuzz_outputs: cannot mount a tmpfs: the full and read-only tricks are skipped")
            return count
        try:
            command = rng.choice(["run", "export", "report"])
            fmt = rng.choice(sorted(FORMATS))
            target = {"run": "out.h5", "export": {"esatan": "out.d", "sinda": "out.sin", "csv": "out-csv", "tmd": "out.TMD"}[fmt],
                      "report": "rep"}[command]
            folder_output = target in ("rep", "out-csv")
            old = mount / (target if not folder_output else "out.h5")
            if size >= 16:
                old.write_bytes(b"the old result\n")
            if readonly and subprocess.run(["mount", "-o", "remount,ro", str(mount)], capture_output=True).returncode:
                print("fuzz_outputs: cannot remount read-only: that trick is skipped")
                continue
            before = digest(old)
            cmd = {"run": [str(args.radnet), "run", str(case)],
                   "export": [str(args.radnet), "export", str(base), "--format", fmt],
                   "report": [str(args.radnet), "report", str(base)]}[command] + ["-o", str(mount / target)]
            rc, out, err = run(cmd, args.work)
            found = contract(rc, out, err)
            if rc != 0 and rc != 4:
                found.append(f"a {size} KiB {'read-only ' if readonly else ''}disk gave exit {rc}, not 4")
            if rc == 4 and digest(old) != before:
                found.append("the old output was changed")
            found += [f"left {t}" for t in temporaries(mount)]
            if rc == 4 and folder_output and (mount / target).exists():
                found.append(f"a partial {target} folder was left")
            for p in found:
                problems.append(f"disk #{i} ({size} KiB{' ro' if readonly else ''}, {' '.join(cmd[1:5])}): {p}: {err.strip()[-200:]}")
        finally:
            unmount(mount)
        count += 1
    return count


# ---- signals -------------------------------------------------------------------------------

def family_signals(args, rng, case, problems):
    folder = args.work / "signals"
    sigs = [signal.SIGTERM, signal.SIGINT, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2,
            signal.SIGALRM, signal.SIGXFSZ, signal.SIGPIPE]
    start = time.monotonic()
    rc, _, _ = run([str(args.radnet), "run", str(case), "-o", "timing.h5", "-q"], args.work)
    span = time.monotonic() - start
    for p in args.work.glob("timing.*"):
        p.unlink()
    if rc != 0:
        problems.append(f"signals: the unsignalled run exited {rc}")
        return 0
    for i in range(args.signals):
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        (folder / "out.h5").write_bytes(b"old result\n")
        (folder / "out.xmf").write_bytes(b"old sidecar\n")
        old = (digest(folder / "out.h5"), digest(folder / "out.xmf"))
        sig = rng.choice(sigs)
        delay = rng.uniform(0.0, 1.2 * span)
        proc = subprocess.Popen([str(args.radnet), "run", str(case), "-o", "out.h5", "-q"], cwd=folder,
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        time.sleep(delay)
        try:
            proc.send_signal(sig)
        except ProcessLookupError:
            pass
        _, err = proc.communicate(timeout=120)
        now = (digest(folder / "out.h5"), digest(folder / "out.xmf"))
        found = []
        if (now[0] == old[0]) != (now[1] == old[1]):
            found.append("a mixed pair: one of out.h5 and out.xmf is old, the other new")
        if now[0] != old[0] and now[0] is not None:
            try:
                with h5py.File(folder / "out.h5", "r") as f:
                    f["nodes/name"][()]
            except Exception as e:  # noqa: BLE001 - any failure to read is the finding
                found.append(f"the new out.h5 is not a readable result ({e})")
        if None in now:
            found.append("the old output was removed")
        if proc.returncode > 0 and proc.returncode not in (0,):
            found.append(f"exit {proc.returncode} after {signal.Signals(sig).name}")
        found += [f"left {t}" for t in temporaries(folder)]
        for p in found:
            problems.append(f"signals #{i} ({signal.Signals(sig).name} at {delay:.3f} s): {p}: {err.decode()[-200:]}")
    return args.signals


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("radnet", type=pathlib.Path)
    ap.add_argument("source", type=pathlib.Path)
    ap.add_argument("work", type=pathlib.Path)
    ap.add_argument("--seed", type=int, default=38)
    ap.add_argument("--results", type=int, default=200)
    ap.add_argument("--reports", type=int, default=10)
    ap.add_argument("--signals", type=int, default=30)
    ap.add_argument("--imports", type=int, default=60)
    args = ap.parse_args()
    args.radnet = args.radnet.resolve()
    args.work = args.work.resolve()
    shutil.rmtree(args.work, ignore_errors=True)
    args.work.mkdir(parents=True)
    case = (args.source / CASE).resolve()
    rc, _, err = run([str(args.radnet), "run", str(case), "-o", "base.h5", "-q"], args.work)
    if rc != 0:
        print(f"fuzz_outputs: the base case failed ({rc}): {err}")
        return 1
    base = args.work / "base.h5"
    rng = random.Random(args.seed)
    problems = []
    args.tally = {}
    counts = {"results": family_results(args, rng, base, problems),
              "files": family_files(args, rng, base, case, problems),
              "imports": family_imports(args, rng, problems),
              "signals": family_signals(args, rng, case, problems)}
    for p in problems:
        print(p)
    print("fuzz_outputs: malformed results by exit code: " + ", ".join(f"{k}: {v}" for k, v in sorted(args.tally.items())))
    total = sum(counts.values())
    print(f"fuzz_outputs: {total} probes ({', '.join(f'{k} {v}' for k, v in counts.items())}), "
          f"{len(problems)} problem(s), {100.0 * (total - len(problems)) / max(total, 1):.1f} % held")
    if not problems:
        shutil.rmtree(args.work, ignore_errors=True)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
