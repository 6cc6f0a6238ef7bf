#!/usr/bin/python3
"""Time against error for the exact method and View3D (bench_exact_view_factors' CSV).

Usage: plot_exact_benchmark.py IN.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# View3D prints 6 decimals: errors under its rounding are drawn at the rounding.
FLOOR = 1e-16


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    scenes = sorted({r["scene"] for r in rows}, key=lambda s: [r["scene"] for r in rows].index(s))
    fig, ax = plt.subplots(figsize=(10, 5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, scene in enumerate(scenes):
        for tool, marker in (("radnet exact", "o"), ("View3D 4.0", "s")):
            pts = [(float(r["seconds"]), max(float(r["max_error"]), FLOOR)) for r in rows
                   if r["scene"] == scene and r["tool"] == tool]
            if not pts:
                continue
            pts.sort(key=lambda p: -p[1])
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=marker, color=colours[k % len(colours)],
                    linestyle="-" if tool.startswith("radnet") else "--", label=f"{scene}, {tool}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time, one thread (s)")
    ax.set_ylabel("largest view-factor error (–)")
    ax.set_title("Exact view factors against View3D: time against error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    fig.savefig(dst, dpi=120)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
