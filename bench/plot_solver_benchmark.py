#!/usr/bin/env python3
"""Pareto plot of docs/solver-benchmark.md: time against error of every band-solve method,
per network size, and each network's eigenvalue decay (issue 12).

    plot_solver_benchmark.py docs/solver-benchmark.md docs/solver-eigenvalues.csv OUT.png
"""
import csv
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def tables(md_path):
    """{n: [(method, setup + solve s, max rel. error)]} from the Markdown tables."""
    out, n = {}, None
    for line in open(md_path, encoding="utf-8"):
        m = re.match(r"## m = \d+: n = (\d+) nodes", line)
        if m:
            n = int(m.group(1))
            out[n] = []
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if n is None or len(cells) < 5 or cells[0] in ("method",) or set(cells[0]) <= {"-"}:
            continue
        try:
            out[n].append((cells[0], float(cells[1]) + float(cells[2]), float(cells[4])))
        except ValueError:
            pass
    return out


def family(method):
    for key in ("dense LU", "refinement to 1e-10", "refinement to 1e-3", "low-rank core", "Jacobi", "Gauss",
                "Southwell", "CG", "eigenvector iteration"):
        if key in method:
            return key
    return method


def main():
    md, decay_csv, out = sys.argv[1:4]
    data = tables(md)
    markers = dict(zip(["dense LU", "refinement to 1e-10", "refinement to 1e-3", "low-rank core", "Jacobi", "Gauss",
                        "Southwell", "CG", "eigenvector iteration"], "o^v<sDPX*"))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for c, (n, rows) in zip(colours, sorted(data.items())):
        seen = set()
        for method, seconds, error in rows:
            f = family(method)
            ax.scatter(seconds, max(error, 1e-16), color=c, marker=markers.get(f, "o"), s=40,
                       label=f"{f}" if f not in seen and n == min(data) else None)
            seen.add(f)
        ax.plot([], [], color=c, label=f"n = {n}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("setup + solve of 360 right-hand sides, s (Eigen, one thread)")
    ax.set_ylabel("max relative error against dense LU (0 drawn at 1e-16)")
    ax.set_title("Band solves: time against error (lower left is better)")
    ax.axhline(1e-3, color="grey", lw=0.8, ls="--")
    ax.text(ax.get_xlim()[0] * 1.1, 1.3e-3, "budget's solver tolerance 1e-3", fontsize=8, color="grey")
    ax.legend(fontsize=7, ncol=2)
    decay = {}
    with open(decay_csv) as f:
        for row in csv.DictReader(f):
            decay.setdefault(int(row["n"]), []).append(float(row["relative_magnitude"]))
    for c, (n, values) in zip(colours, sorted(decay.items())):
        bx.plot(range(1, len(values) + 1), values, color=c, label=f"n = {n} ({len(values)} pairs computed)")
    bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_xlabel("eigenpair index i")
    bx.set_ylabel("|λ_i| / |λ_1|")
    bx.set_title("Eigenvalue decay of G (closed box room)")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
