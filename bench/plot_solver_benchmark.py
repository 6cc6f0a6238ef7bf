#!/usr/bin/env python3
"""Pareto plot of a band-solver benchmark (docs/solver-benchmark.md for the box rooms,
docs/solver-satellite-benchmark.md for the satellites): time against error of every
band-solve method per scene, and each scene's eigenvalue decay (issue 12).

    plot_solver_benchmark.py BENCHMARK.md EIGENVALUES.csv OUT.png
"""
import csv
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def tables(md_path):
    """{(n, scene): [(method, setup + solve s, max rel. error)]} from the Markdown tables."""
    out, n = {}, None
    for line in open(md_path, encoding="utf-8"):
        m = re.match(r"## (.*): n = (\d+) nodes", line)
        if m:
            n = (int(m.group(2)), m.group(1))
            out[n] = []
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if n is None or len(cells) < 6 or cells[0] in ("method",) or set(cells[0]) <= {"-"}:
            continue
        try:
            out[n].append((cells[0], float(cells[1]) + float(cells[2]), float(cells[5])))
        except ValueError:
            pass
    return out


FAMILIES = ["dense LU", "sparse LU", "a-posteriori rank, refined to the budget", "refinement to 1e-10",
            "refinement to the budget", "low-rank core", "Jacobi", "Gauss", "Southwell", "CG", "eigenvector iteration"]


def family(method):
    if "1e-10" in method:
        return "refinement to 1e-10"
    if "a-posteriori" in method:
        return "a-posteriori rank, refined to the budget" if "budget" in method else "a-posteriori rank"
    if "the budget" in method:
        return "refinement to the budget"
    for key in FAMILIES:
        if key in method:
            return key
    return method


def main():
    md, decay_csv, out = sys.argv[1:4]
    data = tables(md)
    markers = dict(zip(FAMILIES + ["a-posteriori rank"], "oH*^v<sDPXdp"))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 7))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    seen = set()
    for c, (n, rows) in zip(colours, sorted(data.items())):
        for method, seconds, error in rows:
            f = family(method)
            ax.scatter(seconds, max(error, 1e-16), color=c, marker=markers.get(f, "o"), s=40,
                       label=f"{f}" if f not in seen else None)
            seen.add(f)
        ax.plot([], [], color=c, label=f"{n[1]}, n = {n[0]}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("setup + solve of 360 right-hand sides, s")
    ax.set_ylabel("max relative error against dense LU (0 drawn at 1e-16)")
    ax.set_title("Band solves: time against error (lower left is better)")
    ax.axhline(1e-3, color="grey", lw=0.8, ls="--")
    ax.text(ax.get_xlim()[0] * 1.1, 1.3e-3, "1 % budget's largest solver tolerance, 1e-3", fontsize=8, color="grey")
    ax.legend(fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    decay = {}
    with open(decay_csv) as f:
        for row in csv.DictReader(f):
            decay.setdefault((int(row["n"]), row["scene"]), []).append(float(row["relative_magnitude"]))
    for c, (n, values) in zip(colours, sorted(decay.items())):
        bx.plot(range(1, len(values) + 1), values, color=c, label=f"{n[1]}, n = {n[0]} ({len(values)} pairs computed)")
    bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_xlabel("eigenpair index i")
    bx.set_ylabel("|λ_i| / |λ_1|")
    bx.set_title("Eigenvalue decay of G")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
