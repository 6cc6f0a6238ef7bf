#!/usr/bin/python3
"""Pictures of a radnet result (Debian's python3-h5py and python3-matplotlib).

    /usr/bin/python3 docs/plot_results.py RESULT.h5 [OUTDIR]

Writes into OUTDIR (default: next to RESULT.h5, named after it):
  <stem>_loads.png        absorbed solar, albedo and Earth-IR power per node along the orbit,
                          with the eclipse shaded
  <stem>_temperature.png  node temperatures along the orbit (when the result has them)
  <stem>_eigenvalues.png  |λ| of the conductance matrix, kept pairs and truncation bound
"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def text(values):
    return [v.decode() if isinstance(v, bytes) else str(v) for v in values]


def timeline(f):
    """Minutes along the sweep, orbit cases (epochs × betas) laid side by side, and the
    position indices where a new case starts (lines are broken there)."""
    t = f["/orbit/time"][:] / 60.0
    if "/orbit/case" not in f:
        return t, []
    case = f["/orbit/case"][:]
    x = np.empty_like(t)
    offset, breaks = 0.0, []
    for k in np.unique(case):
        idx = np.where(case == k)[0]
        x[idx] = t[idx] - t[idx[0]] + offset
        offset = x[idx[-1]] + 0.05 * (x[idx[-1]] - x[idx[0]] + 1.0)
        if idx[0] > 0:
            breaks.append(idx[0])
    return x, breaks


def broken(x, y, breaks):
    """Inserts NaN at case boundaries so that a line does not join two cases."""
    return np.insert(x, breaks, np.nan), np.insert(y, breaks, np.nan)


def shade_eclipses(ax, t_min, sunlit):
    """Grey bands where the spacecraft is in the Earth's shadow (darker in the umbra)."""
    dark = sunlit < 1.0
    start = None
    for k in range(len(t_min)):
        if dark[k] and start is None:
            start = k
        if start is not None and (not dark[k] or k == len(t_min) - 1):
            ax.axvspan(t_min[start], t_min[k], color="0.85", zorder=0, lw=0)
            start = None


def plot_loads(f, out, stem):
    t, breaks = timeline(f)
    sunlit = f["/orbit/sunlit_fraction"][:]
    names = text(f["/nodes/name"][:])
    fig, axes = plt.subplots(3, 1, figsize=(10, 10), sharex=True)
    for ax, key, label in zip(axes, ["solar", "albedo", "earth_ir"], ["direct solar", "albedo", "Earth IR"]):
        data = f["/loads/" + key][:]
        shade_eclipses(ax, t, sunlit)
        for i, name in enumerate(names):
            if np.any(data[:, i] > 0):
                ax.plot(*broken(t, data[:, i], breaks), label=name, lw=1.2)
        ax.set_ylabel(f"absorbed {label} [W]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, ncol=3, loc="upper right")
    axes[-1].set_xlabel("time since each orbit case's epoch [min], cases side by side  (grey: eclipse)")
    fig.suptitle(f"{f['/meta'].attrs['case_name']}: absorbed environmental power per node")
    fig.tight_layout()
    path = os.path.join(out, stem + "_loads.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_temperature(f, out, stem):
    t, breaks = timeline(f)
    temp = f["/solution/temperature"][:]
    names = text(f["/nodes/name"][:])
    fig, ax = plt.subplots(figsize=(10, 5))
    shade_eclipses(ax, t, f["/orbit/sunlit_fraction"][:])
    for i, name in enumerate(names):
        ax.plot(*broken(t, temp[:, i] - 273.15, breaks), label=name, lw=1.2)
    ax.set_xlabel("time since each orbit case's epoch [min], cases side by side  (grey: eclipse)")
    ax.set_ylabel("temperature [°C]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3)
    fig.tight_layout()
    path = os.path.join(out, stem + "_temperature.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_eigenvalues(f, out, stem):
    values = np.abs(f["/eigen/values"][:])
    bound = f["/eigen"].attrs.get("largest_dropped_eigenvalue_bound", 0.0)
    if not np.any(values > 0):  # e.g. a single plate: G = 0, nothing to draw on a log scale
        return None
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.semilogy(np.arange(1, len(values) + 1), values, "o-", label="kept |λ|")
    if bound > 0:
        ax.axhline(bound, color="C3", ls="--", label="largest dropped |λ| (bound)")
    ax.set_xlabel("index k")
    ax.set_ylabel("|λ_k| of G [m²]")
    ax.set_title(f"eigenvalue spectrum, rank {int(f['/eigen'].attrs['rank'])} ({f['/eigen'].attrs['method']})")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    path = os.path.join(out, stem + "_eigenvalues.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    result = argv[1]
    out = argv[2] if len(argv) > 2 else os.path.dirname(os.path.abspath(result))
    os.makedirs(out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(result))[0]
    written = []
    with h5py.File(result, "r") as f:
        if "/orbit/time" in f:
            written.append(plot_loads(f, out, stem))
        if "/solution/temperature" in f and "/orbit/time" in f:
            written.append(plot_temperature(f, out, stem))
        if "/eigen/values" in f:
            written.append(plot_eigenvalues(f, out, stem))
    for path in written:
        if path:
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
