#!/usr/bin/python3
"""Deterministic fuzzing of radnet's inputs (issue 13): the shipped case files and a set of
small meshes are mutated with fixed seeds, and each mutant goes through `radnet validate`
(and, for the cheap seeds, `radnet run`) under a memory cap. Whatever the input, radnet must

  * exit 0, 2, 3 or 4, never crash, hang or exit 1 (1 means "a check failed");
  * on exit 2, name the file, line and column (`file:line:column:`) or, for a file that
    cannot be read at all, the file;
  * leave no file behind unless it succeeded (and then only the result and its sidecars);
  * write no NaN or Inf into any dataset or attribute of a result.

Usage: fuzz_cases.py RADNET SOURCE_DIR WORK_DIR [--mutations N] [--seed S] [--no-memory-cap]
Exit 0 when every mutant kept the contract; otherwise the failures are listed (with the
mutant kept under WORK_DIR/failures) and the exit code is 1.
"""
import argparse
import concurrent.futures
import os
import random
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

# Cheap enough to run in full (well under a second each); the others are validated only.
RUN_SEEDS = {"parallel-plates", "lumped-nodes", "infinite-parallel-plates", "two-sided-panel",
             "sunlit-plate-temperature", "parallel-plates-temperature", "perpendicular-squares",
             "mesh-plate-stl", "mesh-plate-off", "mesh-plate-ply", "mesh-plate-obj", "mesh-plate-binary-stl",
             "mesh-plate-binary-off", "mesh-plate-binary-ply", "mesh-plate-bdf", "mesh-plate-bdf-large",
             "mesh-plate-bdf-free", "mesh-plate-msh", "mesh-plate-msh-22", "mesh-plate-binary-msh",
             "mesh-plate-binary-msh-22", "mesh-plate-obj-normals", "mesh-plate-ply-normals",
             "mesh-plate-binary-ply-normals"}
INTERESTING_NUMBERS = ["0", "-0", "-1", "1", "0.5", "1e308", "-1e308", "1e-308", "4.9e-324", "2147483648",
                       "-2147483649", "9223372036854775808", "1e9", "1e15", "3", "100000000", "0x10", "1_000",
                       ".nan", ".inf", "-.inf", "nan", "1e", "--1", "1.5.2", "360", "-360", "90", "180", "1e-9"]
INTERESTING_SCALARS = ["~", "null", "[]", "{}", "true", "''", '""', "[1, 2]", "{a: 1}", "&anchor 1", "*nowhere",
                       "!!binary AAAA", "x" * 300, "\"\\u0000\"", "'\xff\xfe'", "é", "- 1", "|", ">"]
INTERESTING_BYTES = [b"[", b"]", b"{", b"}", b":", b",", b"- ", b"#", b"'", b'"', b"\t", b"\x00", b"\xff", b"&a ",
                     b"*a", b"\n", b"  ", b"!", b"%YAML 1.2\n", b"---\n", b"...\n", b"? ", b"<<: ", b"\r"]
# Orbit cases of a second or two: run now and then, so that mutants reach the sweep, the loads
# and the thermal solve.
SOMETIMES_RUN_SEEDS = {"cubesat-3u", "satellite", "cubesat-hot-cold", "seed-room", "random-network"}
LOCATED = re.compile(r"[^\s:]+:\d+:\d+:")


def plate_meshes():
    """A 1 m square of two triangles in each mesh format radnet reads, as bytes."""
    v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    tris = [(0, 1, 2), (0, 2, 3)]
    off = "OFF\n4 2 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in v) + "".join(f"3 {a} {b} {c}\n" for a, b, c in tris)
    obj = "o plate\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in v) + "".join(
        f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)
    ply = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 2\nproperty list uchar int vertex_indices\nend_header\n" +
           "".join(f"{x} {y} {z}\n" for x, y, z in v) + "".join(f"3 {a} {b} {c}\n" for a, b, c in tris))
    stl = "solid plate\n"
    for t in tris:
        stl += "facet normal 0 0 1\nouter loop\n" + "".join(
            "vertex {} {} {}\n".format(*v[i]) for i in t) + "endloop\nendfacet\n"
    stl += "endsolid plate\n"
    binary = bytearray(b"radnet fuzz plate".ljust(80, b" ")) + struct.pack("<I", len(tris))
    for t in tris:
        binary += struct.pack("<3f", 0, 0, 1)
        for i in t:
            binary += struct.pack("<3f", *v[i])
        binary += struct.pack("<H", 0)
    binary_off = b"OFF BINARY\n" + struct.pack(">3i", 4, 2, 0) + b"".join(struct.pack(">3f", *p) for p in v) + \
        b"".join(struct.pack(">4i", 3, *t) for t in tris)
    binary_ply = (b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                  b"property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n" +
                  b"".join(struct.pack("<3f", *p) for p in v) + b"".join(struct.pack("<B3i", 3, *t) for t in tris))
    # Vertex normals (specular reflection follows them): OBJ corners `v/vt/vn`, `v//vn` and a
    # negative index; PLY nx, ny, nz, ASCII and binary.
    obj_normals = ("o plate\n" + "".join(f"v {x} {y} {z}\n" for x, y, z in v) + "vt 0 0\nvn 0 0 1\nvn 0 0.6 0.8\n"
                   "f 1/1/1 2/1/1 3/1/2\nf 1//1 3//2 4//-1\n")
    ply_normals = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                   "property float nx\nproperty float ny\nproperty float nz\n"
                   "element face 2\nproperty list uchar int vertex_indices\nend_header\n" +
                   "".join(f"{x} {y} {z} 0 0 1\n" for x, y, z in v) + "".join(f"3 {a} {b} {c}\n" for a, b, c in tris))
    binary_ply_normals = (b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
                          b"property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                          b"property float nz\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n" +
                          b"".join(struct.pack("<6f", *p, 0, 0, 1) for p in v) +
                          b"".join(struct.pack("<B3i", 3, *t) for t in tris))
    out = {"stl": stl.encode(), "off": off.encode(), "ply": ply.encode(), "obj": obj.encode(),
           "binary-stl": bytes(binary), "binary-off": binary_off, "binary-ply": binary_ply,
           "obj-normals": obj_normals.encode(), "ply-normals": ply_normals.encode(),
           "binary-ply-normals": binary_ply_normals}
    out.update(nastran_plates(v))
    out.update(gmsh_plates(v))
    return out


def nastran_plates(v):
    """The plate as NASTRAN bulk data: small field (a CQUAD4), large field (GRID* with `*`
    continuations, in a CORD2R), free field (commas, two CTRIA3, short-form reals)."""
    def small(*fields):
        return "".join(str(f)[:8].ljust(8) for f in fields).rstrip() + "\n"
    grids = "".join(small("GRID", k + 1, "", f"{x}.", f"{y}.", f"{z}.") for k, (x, y, z) in enumerate(v))
    plate = "BEGIN BULK\n" + grids + small("CQUAD4", 10, 1, 1, 2, 3, 4) + small("PSHELL", 1, 1, "0.002") + \
        small("MAT4", 1, "167.") + "ENDDATA\n"
    large = small("CORD2R", 3, 0, "0.", "0.", "0.", "0.", "0.", "1.", "+C3") + small("+C3", "1.", "0.", "0.")
    for k, (x, y, z) in enumerate(v):
        large += f"GRID*   {k + 1:<16d}{3:<16d}{float(x):<16.6f}{float(y):<16.6f}*G{k}\n*G{k:<6d}{float(z):<16.6f}\n"
    large += small("CTRIA3", 11, 2, 1, 2, 3) + small("CTRIA3", 12, 2, 1, 3, 4)
    free = "".join(f"GRID,{k + 1},,{x}.0+0,{y}.,{z}.\n" for k, (x, y, z) in enumerate(v)) + \
        "CTRIA3,21,7,1,2,3\nCTRIA3,22,7,1,3,4\nPSHELL,7,,1.-3\n"
    return {"bdf": plate.encode(), "bdf-large": large.encode(), "bdf-free": free.encode()}


def gmsh_plates(v):
    """The plate as Gmsh MSH 2.2 and 4.1, ASCII and binary: one quadrangle in physical
    surface 1 ("plate") and a line element that is read past."""
    names = "$PhysicalNames\n1\n2 1 \"plate\"\n$EndPhysicalNames\n"
    out = {}
    for binary in (False, True):
        fmt = (lambda version: f"$MeshFormat\n{version} {int(binary)} 8\n".encode() +
               (struct.pack("<i", 1) + b"\n" if binary else b"") + b"$EndMeshFormat\n" + names.encode())
        if binary:
            nodes = b"$Nodes\n4\n" + b"".join(struct.pack("<i3d", k + 1, *map(float, p)) for k, p in enumerate(v))
            elements = (b"\n$EndNodes\n$Elements\n2\n" + struct.pack("<3i", 1, 1, 2) + struct.pack("<5i", 1, 0, 9, 1, 2) +
                        struct.pack("<3i", 3, 1, 2) + struct.pack("<7i", 2, 1, 9, 1, 2, 3, 4) + b"\n$EndElements\n")
        else:
            nodes = ("$Nodes\n4\n" + "".join(f"{k + 1} {x} {y} {z}\n" for k, (x, y, z) in enumerate(v))).encode()
            elements = b"$EndNodes\n$Elements\n2\n1 1 2 0 9 1 2\n2 3 2 1 9 1 2 3 4\n$EndElements\n"
        out[("binary-" if binary else "") + "msh-22"] = fmt("2.2") + nodes + elements
        if binary:
            q = lambda *a: struct.pack(f"<{len(a)}Q", *a)
            i = lambda *a: struct.pack(f"<{len(a)}i", *a)
            body = (b"$Entities\n" + q(0, 0, 1, 0) + i(9) + struct.pack("<6d", 0, 0, 0, 1, 1, 0) + q(1) + i(1) + q(0) +
                    b"\n$EndEntities\n$Nodes\n" + q(1, 4, 1, 4) + i(2, 9, 0) + q(4) + q(1, 2, 3, 4) +
                    b"".join(struct.pack("<3d", *map(float, p)) for p in v) + b"\n$EndNodes\n$Elements\n" +
                    q(1, 1, 1, 1) + i(2, 9, 3) + q(1) + q(1, 1, 2, 3, 4) + b"\n$EndElements\n")
        else:
            body = ("$Entities\n0 0 1 0\n9 0 0 0 1 1 0 1 1 0\n$EndEntities\n$Nodes\n1 4 1 4\n2 9 0 4\n1\n2\n3\n4\n" +
                    "".join(f"{x} {y} {z}\n" for x, y, z in v) +
                    "$EndNodes\n$Elements\n1 1 1 1\n2 9 3 1\n1 1 2 3 4\n$EndElements\n").encode()
        out[("binary-" if binary else "") + "msh"] = fmt("4.1") + body
    return out


def mesh_case(ext):
    """A plate from a mesh file facing a plate from a rectangle, at 300 K and 200 K (one node
    `part` from any format: NASTRAN and Gmsh files are split by group unless told)."""
    single = ", nodes: single" if ext in ("bdf", "msh") else ""
    return f"""name: mesh-plate
materials:
  black: {{emissivity: 1.0, absorptivity: 1.0}}
geometry:
  - mesh: {{name: part, file: part.{ext}, scale: 1.0, front: black{single}}}
  - rectangle: {{name: facing, origin: [0, 1, 1], u: [1, 0, 0], v: [0, -1, 0], front: black, subdivisions: [2, 2]}}
solver:
  view_factors: {{rays: 2000, seed: 1}}
thermal:
  nodes: {{part: {{capacitance: 100.0, dissipation: 10.0}}, facing: {{capacitance: 100.0}}}}
  conductors: [[part, facing, 0.5]]
""".encode()


def seeds(source):
    """(name, case bytes, {side file name: bytes}) for every shipped case and every mesh format."""
    out = []
    for folder in ["cases/analytic", "cases/examples", "tests/data/bad"]:
        for path in sorted((source / folder).glob("*.yaml")):
            side = {}
            # Includes and meshes next to the case travel with it (the examples' materials/).
            for sub in ["materials", "meshes"]:
                if (path.parent / sub).is_dir():
                    for f in sorted((path.parent / sub).iterdir()):
                        side[f"{sub}/{f.name}"] = f.read_bytes()
            out.append((("bad-" if folder == "tests/data/bad" else "") + path.stem, path.read_bytes(), side))
    # A STEP solid (OpenCASCADE reads it in a child process: its crashes must become refusals).
    step = (source / "tests/data/meshes/box.step").read_bytes()
    out.append(("mesh-box-step", b"name: step-box\nmaterials: {black: {emissivity: 0.9, absorptivity: 0.9}}\n"
                b"geometry:\n  - mesh: {name: part, file: part.step, front: black}\n", {"part.step": step}))
    # An imported ESATAN network: the case's keys mutated around a real TMD.
    tmd = (source / "tests/data/esatan/DISCTR_TRANSIENT.TMD").read_bytes()
    out.append(("import-disc", b"name: disc\nimport: {esatan_tmd: disc.TMD}\nthermal:\n"
                b"  nodes: {D1000: {capacitance: 2.0}}\n  lumped: {box: {capacitance: 5.0, dissipation: 0.5}}\n"
                b"  conductors: [[box, D1000, 0.1]]\n  transient: {time_step: 20.0}\n", {"disc.TMD": tmd}))
    for fmt, data in plate_meshes().items():
        ext = fmt.replace("binary-", "").split("-")[0]
        out.append((f"mesh-plate-{fmt}", mesh_case(ext), {f"part.{ext}": data}))
    return out


def mutate_text(rng, data, op=None):
    text = data.decode("utf-8", "surrogateescape")
    lines = text.split("\n")
    op = rng.randrange(9) if op is None else op
    if op == 0:  # a number → an interesting one
        spots = list(re.finditer(r"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?", text))
        if spots:
            m = rng.choice(spots)
            text = text[:m.start()] + rng.choice(INTERESTING_NUMBERS) + text[m.end():]
    elif op == 1:  # a value → an interesting scalar or structure
        spots = list(re.finditer(r": +([^\s{}\[\],#]+)", text))
        if spots:
            m = rng.choice(spots)
            text = text[:m.start(1)] + rng.choice(INTERESTING_SCALARS) + text[m.end(1):]
    elif op == 2 and len(lines) > 1:  # delete a line
        del lines[rng.randrange(len(lines))]
        text = "\n".join(lines)
    elif op == 3:  # duplicate a line
        k = rng.randrange(len(lines))
        lines.insert(k, lines[k])
        text = "\n".join(lines)
    elif op == 4 and len(lines) > 1:  # swap two lines
        a, b = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[a], lines[b] = lines[b], lines[a]
        text = "\n".join(lines)
    elif op == 5:  # a key misspelt
        spots = list(re.finditer(r"([A-Za-z_]+):", text))
        if spots:
            m = rng.choice(spots)
            key = m.group(1)
            k = rng.randrange(len(key))
            text = text[:m.start(1)] + key[:k] + key[k + 1:] + rng.choice(["", "s", "_x"]) + text[m.end(1):]
    elif op == 6:  # indentation moved
        k = rng.randrange(len(lines))
        lines[k] = ("  " + lines[k]) if rng.random() < 0.5 else lines[k][2:]
        text = "\n".join(lines)
    elif op == 7:  # a block repeated (aliases, repeated primitives)
        a = rng.randrange(len(lines))
        b = min(len(lines), a + rng.randrange(1, 6))
        lines[b:b] = lines[a:b] * rng.randrange(1, 4)
        text = "\n".join(lines)
    else:  # byte-level
        return mutate_bytes(rng, data)
    return text.encode("utf-8", "surrogateescape")


def mutate_bytes(rng, data):
    data = bytearray(data)
    op = rng.randrange(5)
    if not data:
        return bytes(rng.choice(INTERESTING_BYTES))
    k = rng.randrange(len(data))
    if op == 0:
        data[k] = rng.randrange(256)
    elif op == 1:
        data[k:k] = rng.choice(INTERESTING_BYTES)
    elif op == 2:
        del data[k:k + rng.randrange(1, 16)]
    elif op == 3:
        data = data[:k]  # truncated
    else:
        span = data[k:k + rng.randrange(1, 64)]
        data[k:k] = span * rng.randrange(1, 4)
    return bytes(data)


def mutate_mesh(rng, name, data):
    if name.endswith((".off", ".ply")) and b"binary" in data[:64].lower():
        return mutate_bytes(rng, data)
    if name.endswith(".msh") and b" 1 8" in data[:40]:  # binary Gmsh: counts, tags and doubles
        return mutate_bytes(rng, data)
    if name.endswith(".stl") and not data.startswith(b"solid"):  # binary STL: counts and floats
        data = bytearray(data)
        op = rng.randrange(3)
        if op == 0 and len(data) >= 84:
            data[80:84] = struct.pack("<I", rng.choice([0, 1, 3, 2**31, 2**32 - 1, 1000]))
        elif op == 1 and len(data) > 96:
            k = 84 + 12 + 4 * rng.randrange(9)
            data[k:k + 4] = struct.pack("<f", rng.choice([float("nan"), float("inf"), 1e30, 0.0, -1e-30]))
        else:
            return mutate_bytes(rng, bytes(data))
        return bytes(data)
    return mutate_text(rng, data)


def mutant(rng, seed):
    name, case, side = seed
    side = dict(side)
    if rng.random() < 0.5:  # one value changed in a case that stays well-formed: reaches the physics
        return name, mutate_text(rng, case, op=rng.choice([0, 0, 1])), side
    for _ in range(rng.randrange(1, 4)):
        meshes = [k for k in side if not k.endswith(".yaml")]
        if meshes and rng.random() < 0.4:
            k = rng.choice(meshes)
            side[k] = mutate_mesh(rng, k, side[k])
        elif side and rng.random() < 0.1:
            k = rng.choice(sorted(side))
            side[k] = mutate_text(rng, side[k])
        else:
            case = mutate_text(rng, case)
    return name, case, side


def finite_h5(path):
    """The datasets and attributes of `path` holding a NaN or an Inf."""
    bad = []

    def floats_ok(value):
        a = np.asarray(value)
        return not (a.dtype.kind in "fc" and not np.all(np.isfinite(a)))

    def visit(name, obj):
        for k, v in obj.attrs.items():
            if not floats_ok(v):
                bad.append(f"{name} attribute {k}")
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fc" and not floats_ok(obj[()]):
            bad.append(name)

    with h5py.File(path, "r") as f:
        for k, v in f.attrs.items():
            if not floats_ok(v):
                bad.append(f"/ attribute {k}")
        f.visititems(visit)
    return bad


def limit_memory(cap_bytes):
    def apply():
        if cap_bytes:
            resource.setrlimit(resource.RLIMIT_AS, (cap_bytes, cap_bytes))
        os.setsid()
    return apply


def write_mutant(args, index, mutated):
    name, case, side = mutated
    folder = args.work / f"m{index:05d}"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / "case.yaml").write_bytes(case)
    for k, v in side.items():
        (folder / k).parent.mkdir(parents=True, exist_ok=True)
        (folder / k).write_bytes(v)
    return folder, {p.relative_to(folder) for p in folder.rglob("*")}


def execute(args, cmd, cwd):
    """(exit code or None when stopped for time, stderr text, problems)."""
    problems = []
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            preexec_fn=limit_memory(args.memory_cap))
    try:
        out, err = proc.communicate(timeout=args.timeout)
        return proc.returncode, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), problems
    except subprocess.TimeoutExpired:
        # A heavy but valid mutant (rays × 1e4) runs long: stop it as a user would (SIGTERM)
        # and hold it to the same rule: nothing left behind.
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            out, err = proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
            problems.append("did not stop within 30 s of SIGTERM")
        return None, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), problems


def judge(rc, err_text, located_as, run):
    problems = []
    if rc is None:
        if not run:
            problems.append("validate did not finish in time")
        return problems
    if rc < 0:
        problems.append(f"killed by signal {-rc} (a crash)")
    elif rc not in (0, 2, 3, 4):
        problems.append(f"exit {rc}")
    # Located in the mutant's own folder: the case, an include or a mesh it names.
    if rc == 2 and not re.search(re.escape(located_as) + r"[^\s:]*:\d+:\d+:", err_text) and \
            not re.search(re.escape(located_as) + r"[^\s:]*\.(yaml|yml|stl|off|ply|obj|bdf|msh|step)\b", err_text, re.I):
        problems.append("exit 2 without file:line:column")
    if rc not in (0, None) and not err_text.strip():
        problems.append(f"exit {rc} with nothing said on stderr")
    return problems


def leftovers(folder, before, allowed):
    after = {p.relative_to(folder) for p in folder.rglob("*")}
    new = sorted(str(p) for p in after - before)
    return [p for p in new if p not in allowed and not (allowed and re.fullmatch(r"out(\.[\w.+-]+)?\.xmf", p))]


def finish(args, index, name, folder, problems, err_text):
    if problems:
        keep = args.work / "failures" / f"m{index:05d}-{name}"
        shutil.rmtree(keep, ignore_errors=True)
        shutil.copytree(folder, keep)
        (keep / "stderr.txt").write_text(err_text)
    shutil.rmtree(folder, ignore_errors=True)


def run_one(args, index, mutated):
    """`radnet run` of one cheap mutant: the contract, leftovers and a finite result."""
    folder, before = write_mutant(args, index, mutated)
    cmd = [args.radnet, "run", "case.yaml", "--threads", "1", "-o", "out.h5", "-q"]
    rc, _, err, problems = execute(args, cmd, folder)
    problems += judge(rc, err, "", True)
    left = leftovers(folder, before, {"out.h5"} if rc == 0 else set())
    if left:
        problems.append(f"left behind: {', '.join(left[:5])}")
    if rc == 0 and (folder / "out.h5").exists():
        bad = finite_h5(folder / "out.h5")
        if bad:
            problems.append(f"NaN or Inf in {', '.join(bad[:5])}")
    finish(args, index, mutated[0], folder, problems, err)
    return [(index, mutated[0], True, rc, problems, err.strip().splitlines()[-1:])]


def validate_batch(args, batch):
    """`radnet validate` of many mutants in one process (process start-up dominates a
    validation); a batch whose outcome cannot be told apart per file is validated again one
    file at a time."""
    written = [(index, mutated) + write_mutant(args, index, mutated) for index, mutated in batch]
    paths = [f"m{index:05d}/case.yaml" for index, *_ in written]
    rc, out, err, problems = execute(args, [args.radnet, "validate"] + paths, args.work)
    valid = {line.split(": valid")[0] for line in out.splitlines() if ": valid (" in line}
    said = {p for p in paths if p not in valid and re.search(re.escape(p.split("/")[0]) + r"/[^\s:]*:\d+:\d+:", err)}
    one_by_one = rc is None or rc < 0 or rc not in (0, 2, 3, 4) or problems or len(valid) + len(said) < len(paths)
    results = []
    for (index, mutated, folder, before), path in zip(written, paths):
        if one_by_one and path not in valid and path not in said:
            frc, _, ferr, fproblems = execute(args, [args.radnet, "validate", path], args.work)
            fproblems += judge(frc, ferr, path.split("/")[0] + "/", False)
        else:
            frc, ferr, fproblems = (0 if path in valid else 2), "", []
        left = leftovers(folder, before, set())
        if left:
            fproblems.append(f"left behind: {', '.join(left[:5])}")
        finish(args, index, mutated[0], folder, fproblems, ferr)
        results.append((index, mutated[0], False, frc, fproblems, ferr.strip().splitlines()[-1:]))
    return results


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("radnet")
    ap.add_argument("source", type=Path)
    ap.add_argument("work", type=Path)
    ap.add_argument("--mutations", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--batch", type=int, default=40)
    ap.add_argument("--memory-cap-gib", type=float, default=4.0)
    ap.add_argument("--no-memory-cap", action="store_true", help="for sanitizer builds, which reserve terabytes")
    args = ap.parse_args()
    args.radnet = str(Path(args.radnet).resolve())
    args.memory_cap = 0 if args.no_memory_cap else int(args.memory_cap_gib * 2**30)
    shutil.rmtree(args.work, ignore_errors=True)
    args.work.mkdir(parents=True)
    corpus = seeds(args.source.resolve())
    good = [c for c in corpus if not c[0].startswith("bad-")]
    rng = random.Random(args.seed)
    runs, validations = [], []
    for index in range(args.mutations):
        # Mostly valid seeds (a mutant of a valid case reaches deeper), a fifth from the bad ones.
        seed = rng.choice(good) if rng.random() < 0.8 else rng.choice(corpus)
        mutated = mutant(rng, seed)
        if (seed[0] in RUN_SEEDS and rng.random() < 0.3) or (seed[0] in SOMETIMES_RUN_SEEDS and rng.random() < 0.1):
            runs.append((index, mutated))
        else:
            validations.append((index, mutated))
    jobs = [lambda j=j: run_one(args, *j) for j in runs]
    jobs += [lambda b=validations[k:k + args.batch]: validate_batch(args, b)
             for k in range(0, len(validations), args.batch)]
    start = time.time()
    failures, exits, stopped = [], {}, 0
    with concurrent.futures.ThreadPoolExecutor(args.workers) as pool:
        for results in pool.map(lambda job: job(), jobs):
            for index, name, run, rc, problems, last in results:
                exits[(run, rc)] = exits.get((run, rc), 0) + 1
                stopped += rc is None
                if problems:
                    failures.append((index, name, run, rc, problems, last))
    took = time.time() - start
    cap = f"memory cap {args.memory_cap / 2**30:.1f} GiB" if args.memory_cap else "no memory cap"
    print(f"{args.mutations} mutants of {len(corpus)} seeds ({len(runs)} run in full, {len(validations)} validated) "
          f"in {took:.1f} s, {cap}")
    print("exit codes: " + ", ".join(f"{'run' if r else 'validate'} {'stopped' if c is None else c}: {n}"
                                     for (r, c), n in sorted(exits.items(), key=lambda x: (x[0][0], x[0][1] or -99))))
    if stopped:
        print(f"{stopped} run(s) stopped by SIGTERM after {args.timeout} s (heavy but valid mutants), nothing left behind")
    for index, name, run, rc, problems, last in sorted(failures)[:40]:
        print(f"FAIL mutant {index} of {name} ({'run' if run else 'validate'}, exit {rc}): {'; '.join(problems)}"
              f"{' | ' + last[0] if last else ''}")
    if not failures:
        shutil.rmtree(args.work, ignore_errors=True)
    print(f"{args.mutations - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
