#!/usr/bin/python3
"""End-to-end runs against n: per-stage time and peak memory of `radnet run`, with the
error budget (the default) and with the settings radnet used before it (per-node shadow
rays, 16,384 cosine-weighted planet rays, band solves refined to 1e-10) in the same session,
so that the ratio is measured on one machine. Writes a Markdown table.

usage: bench_end_to_end.py RADNET OUT.md CASE.yaml...
"""
import os
import re
import subprocess
import sys
import tempfile
import time

import h5py

BASELINE = {"environment": "shadow_samples: 1024, planet_rays: 16384, ", "solver": "  tolerance: 1.0e-10\n"}


def variant(path, baseline):
    text = open(path).read()
    if baseline:
        text = re.sub(r"environment: \{", "environment: {" + BASELINE["environment"], text)
        text = re.sub(r"solver:\n", "solver:\n" + BASELINE["solver"], text)
    return text


def run(radnet, case, baseline):
    folder = os.path.dirname(os.path.abspath(case))
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", dir=folder, delete=False) as f:
        f.write(variant(case, baseline))
        yaml = f.name
    out = tempfile.mktemp(suffix=".h5")
    # A child Python of its own runs radnet, so that the peak resident memory it reports
    # (RUSAGE_CHILDREN: the largest of its children) is this run's alone.
    probe = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:]); "
             "sys.stderr.write('peak_kib %d\\n' % resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); "
             "sys.exit(r.returncode)")
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, "-c", probe, radnet, "run", yaml, "-o", out], capture_output=True,
                          text=True)
    wall = time.monotonic() - t0
    peak = int(re.search(r"peak_kib (\d+)", proc.stderr).group(1))
    os.unlink(yaml)
    if proc.returncode != 0:
        raise SystemExit(f"{case}: radnet exited {proc.returncode}\n{proc.stderr[-2000:]}")
    m = re.search(r"wrote .* in ([0-9.]+) s", proc.stderr)
    with h5py.File(out) as h5:
        rep = dict(h5["/report"].attrs)
        n = h5["/nodes/name"].shape[0]
        rank = int(h5["/eigen"].attrs["rank"])
    os.unlink(out)
    xdmf = out[:-3] + ".xdmf"
    if os.path.exists(xdmf):
        os.unlink(xdmf)
    stages = {k[5:-2]: float(v) for k, v in rep.items() if k.startswith("time_") and k.endswith("_s")}
    stages["output"] = float(m.group(1)) if m else 0.0
    return dict(n=n, wall=wall, peak_mib=peak / 1024.0, stages=stages, rank=rank,
                unc=float(rep.get("absorbed_uncertainty_max_relative", float("nan"))),
                shadow=int(rep.get("shadow_rays", 0)), planet=int(rep.get("planet_rays", 0)))


def main():
    radnet, out, cases = sys.argv[1], sys.argv[2], sys.argv[3:]
    cols = ["view_factors", "eigendecomposition", "exchange_factors", "environment_loads", "band_solves",
            "uncertainty", "output"]
    lines = ["| case | n | settings | wall (s) | " + " | ".join(c.replace("_", " ") for c in cols) +
             " | rank | shadow rays | planet rays | largest σ / orbit max | peak memory (MiB) |",
             "|---" * (len(cols) + 10) + "|"]
    for case in cases:
        for baseline in (True, False):
            r = run(radnet, case, baseline)
            name = os.path.basename(case)[:-5]
            label = "before the budget" if baseline else "error budget (default)"
            cells = " | ".join(f"{r['stages'].get(c, 0.0):.2f}" for c in cols)
            lines.append(f"| {name} | {r['n']} | {label} | {r['wall']:.1f} | {cells} | {r['rank']} | "
                         f"{r['shadow']:.3g} | {r['planet']:.3g} | {100 * r['unc']:.2f} % | {r['peak_mib']:.0f} |")
            print(lines[-1], flush=True)
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
