#!/usr/bin/python3
"""The report of a radnet result: Markdown and CSV tables and PNG figures (`radnet report`).

    /usr/bin/python3 docs/radnet_report.py RESULT.h5 OUTDIR [--limits FILE.yaml]

Needs Debian's python3-h5py, python3-numpy and python3-matplotlib. Writes into OUTDIR:
  report.md            the run's warnings (/report/warnings); per design case: node min / time-weighted mean / max temperature,
                       orbit-mean heat flows by kind, heater duty; the hot/cold envelope
                       (against limits when given); the run's speed and error budget
  temperatures.csv     case, node, min_K, mean_K, max_K
  heat_flows.csv       case, node, then each kind of heat flow (orbit mean, W, + into the node)
  heaters.csv          case, heater, node, duty, mean_W
  envelope.csv         node, min_K, min_case, max_K, max_case[, limit_min_K, limit_max_K, margin_K, ok]
  <case>_temperature.png, <case>_loads.png   over the orbit, eclipses shaded, one colour per node
  heat_balance.png     orbit-mean heat flows per node and kind, each design case
  envelope.png         min/max per node over the design cases, against the limits
  budget.png           where the run's time went, and its error budget
  modes.png            the radiative network's exchange modes kept by the eigendecomposition
Limits: the case file's `limits: {node: [min_K, max_K]}` (/limits), or lines
"node: [min_K, max_K]" in FILE.yaml.
Exit: 0 written, 2 not a radnet result, a malformed one (naming the dataset) or bad limits,
4 the directory cannot be written. Every dataset read is checked against /nodes first (shape,
index ranges, finite values, size against the file's); the files are made in a temporary
folder beside OUTDIR and moved into it only when all are made, so a failure writes nothing.
"""
import csv
import os
import re
import shutil
import signal
import sys

try:
    import h5py
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402
except ImportError as missing:  # pragma: no cover - a machine without Debian's packages
    sys.stderr.write(f"radnet report: {missing}: install python3-h5py python3-numpy python3-matplotlib\n")
    sys.exit(4)

KINDS = ["solar", "albedo", "earth_ir", "emitted", "radiative", "conducted", "dissipation", "heater", "stored",
         "boundary"]
MAX_LINES = 14  # nodes drawn one by one; the rest are summed ("others")
MAX_EQUIPMENT = 24  # signed-off nodes (equipment, nodes with limits) drawn one by one at most
MAX_GROUPS = 8  # bands of grouped nodes in a temperature figure


def text(values):
    return [v.decode() if isinstance(v, bytes) else str(v) for v in values]


def fail(code, message):
    sys.stderr.write(f"radnet report: {message}\n")
    sys.exit(code)


class Malformed(Exception):
    """A dataset that is not what radnet writes."""

    def __init__(self, dataset, what):
        super().__init__(f"{dataset}: {what}")


class WriteFailed(Exception):
    """A file of the report could not be written (a full disk, permissions)."""


def check_result(f, path):
    """Checks every dataset the report reads against /nodes before any is used (exit 2 names
    the first that is wrong): shapes, index ranges, finite values, and a logical size no larger
    than the file could hold (a 3 GB dataset declared in a 10 kB file is refused, not read)."""
    budget = 1100 * os.path.getsize(path) + (16 << 20)  # deflate reaches ~1000:1 at most

    def dataset(name, shape=None, integer=False, finite=True, low=None, high=None):
        if name not in f:
            raise Malformed(name, "missing")
        ds = f[name]
        if not isinstance(ds, h5py.Dataset):
            raise Malformed(name, "is a group, not a dataset")
        if ds.dtype.kind not in "biuf" + ("SUOa" if shape == "text" else ""):
            raise Malformed(name, f"holds {ds.dtype}, not numbers")
        if ds.size * max(ds.dtype.itemsize, 1) > budget:
            raise Malformed(name, f"declares {ds.size} entries, more than a {os.path.getsize(path)}-byte file holds")
        if shape not in (None, "text") and (len(ds.shape) != len(shape) or any(
                want is not None and got != want for got, want in zip(ds.shape, shape))):
            raise Malformed(name, f"shape {ds.shape}, expected {tuple('any' if w is None else w for w in shape)}")
        if shape == "text":
            return ds
        data = ds[()]
        if integer and ds.dtype.kind not in "biu":
            raise Malformed(name, f"holds {ds.dtype}, not whole numbers")
        if finite and not np.all(np.isfinite(data)):
            raise Malformed(name, "holds NaN or infinity")
        if low is not None and np.any(data < low):
            raise Malformed(name, f"holds {data.min()}, below {low}")
        if high is not None and np.any(data > high):
            raise Malformed(name, f"holds {data.max()}, above {high}")
        return data

    names = dataset("/nodes/name", "text")
    if len(names.shape) != 1 or names.shape[0] == 0:
        raise Malformed("/nodes/name", f"shape {names.shape}, expected one name per node")
    n = names.shape[0]
    positions = None
    if "/solution/temperature" in f:
        positions = dataset("/solution/temperature", (None, n), low=0.0).shape[0]
    if "/orbit/time" in f:
        time = dataset("/orbit/time", (positions,) if positions else (None,))
        positions = time.shape[0]
        dataset("/orbit/sunlit_fraction", (positions,), low=0.0, high=1.0)
        dataset("/orbit/case", (positions,), integer=True, low=0)
        for kind in ("solar", "albedo", "earth_ir"):
            if dataset(f"/loads/{kind}", (positions, None)).shape[1] > n:
                raise Malformed(f"/loads/{kind}", f"more columns than the {n} nodes")
    if positions is None:
        positions = 1
    cases = 1
    if "/cases/name" in f:
        cases = dataset("/cases/name", "text").shape[0]
        start = dataset("/cases/position_start", (cases + 1,), integer=True, low=0, high=positions)
        if start[0] != 0 or start[-1] != positions or np.any(np.diff(start) < 0):
            raise Malformed("/cases/position_start", f"not 0 … {positions} in order")
    if "/cases/time_weight" in f:
        dataset("/cases/time_weight", (positions,), low=0.0)
    if "/solution/time" in f:
        dataset("/solution/time", (positions,))
    for kind in KINDS:
        if "/solution/heat/" + kind in f:
            dataset("/solution/heat/" + kind, (positions, n))
    if "/heaters/name" in f:
        heaters = dataset("/heaters/name", "text").shape[0]
        node_names = set(text(names[()]))
        for heater_node in text(dataset("/heaters/node", "text")[()]):
            if heater_node not in node_names:
                raise Malformed("/heaters/node", f"'{heater_node}' is not a node")
        dataset("/heaters/power", (positions, heaters), low=0.0)
        if "/heaters/case_duty" in f:
            orbit_cases = dataset("/heaters/case_duty", (None, heaters), low=0.0, high=1.0).shape[0]
            if "/cases/orbit_case_start" in f:
                first = dataset("/cases/orbit_case_start", (cases + 1,), integer=True, low=0, high=orbit_cases)
                if np.any(np.diff(first) < 0) or np.any(first[:-1] >= orbit_cases):
                    raise Malformed("/cases/orbit_case_start", f"not in order below the {orbit_cases} orbit cases")
    if "/solution/envelope/temperature_max" in f:
        for side in ("min", "max"):
            dataset(f"/solution/envelope/temperature_{side}", (n,), low=0.0)
            dataset(f"/solution/envelope/temperature_{side}_case", (n,), integer=True, low=0, high=cases - 1)
    if "/limits/node" in f:
        count = dataset("/limits/node", "text").shape[0]
        dataset("/limits/min", (count,))
        dataset("/limits/max", (count,))
    if "/eigen/values" in f and isinstance(f.get("/network/conductance"), h5py.Dataset):
        dataset("/eigen/values", (None,))
        g = dataset("/network/conductance", "text")
        if len(g.shape) != 2 or g.shape[0] != g.shape[1] or g.shape[0] > n or g.dtype.kind != "f":
            raise Malformed("/network/conductance", f"shape {g.shape} of {g.dtype}, expected square, at most {n} nodes")
    if "/eigen/values" in f and "/network/sparse/conductance/data" in f:
        dataset("/eigen/values", (None,))
        data = dataset("/network/sparse/conductance/data", (None,))
        shape = f["/network/sparse/conductance"].attrs.get("shape")
        try:
            rows = int(shape[0]) if shape is not None and len(shape) == 2 else -1
        except (TypeError, ValueError):
            rows = -1
        if data.dtype.kind != "f" or not 0 <= rows <= n:
            raise Malformed("/network/sparse/conductance", f"data {data.shape} of {data.dtype} with shape attribute "
                            f"{shape}: expected a CSR group of at most {n} rows")
    if "/report/warnings" in f and len(dataset("/report/warnings", "text").shape) != 1:
        raise Malformed("/report/warnings", "expected one text per warning")
    if "/report" in f:
        for key, value in f["/report"].attrs.items():
            if re.fullmatch(r"time_\w+_s|absorbed_uncertainty_\w+|accuracy|view_factor_error|heat_balance_\w+", key):
                try:
                    if not np.isfinite(float(value)):
                        raise ValueError
                except (TypeError, ValueError):
                    raise Malformed(f"/report attribute {key}", f"'{value}' is not a finite number") from None


class Result:
    """What the report needs from a result, per design case."""

    def __init__(self, f):
        self.f = f
        self.name = f["/meta"].attrs["case_name"]
        self.name = self.name.decode() if isinstance(self.name, bytes) else str(self.name)
        self.nodes = text(f["/nodes/name"][()])
        self.thermal = "/solution/temperature" in f
        self.orbit = "/orbit/time" in f
        positions = f["/solution/temperature"].shape[0] if self.thermal else (
            f["/orbit/time"].shape[0] if self.orbit else 1)
        if "/cases/name" in f:
            self.cases = text(f["/cases/name"][()])
            start = f["/cases/position_start"][()]
        else:
            self.cases, start = ["run"], np.array([0, positions])
        self.spans = [np.arange(start[k], start[k + 1]) for k in range(len(self.cases))]
        # radnet's own weights of each position in its case's time mean (the periodic
        # trapezoid over each orbit case's sweep): the report's means are radnet's.
        weight = f["/cases/time_weight"][()] if "/cases/time_weight" in f else None
        if weight is None and "/solution/time" in f and f["/solution/time"].shape[0] > 1:
            t = f["/solution/time"][()]  # a network transient: the trapezoid of its output times
            weight = 0.5 * (np.append(t[1:], t[-1]) - np.insert(t[:-1], 0, t[0]))
            weight /= weight.sum()
        if weight is None and self.thermal and max(len(s) for s in self.spans) > 1:
            sys.stderr.write("radnet report: warning: the result has no /cases/time_weight (an older radnet): "
                             "means are plain averages over the positions, not radnet's time-weighted ones\n")
        self.weights = [weight[span] if weight is not None else np.full(len(span), 1.0 / len(span))
                        for span in self.spans]


def limits_of(result, path):
    """Node limits {name: (min_K, max_K)}: the case file's `limits:` (/limits in the result),
    or, with --limits FILE, lines "node: [min_K, max_K]" of that file, or the same given inline
    ("battery: [275, 310]; radio: [250, 330]")."""
    limits = {}
    entry = r"['\"]?([\w.+\-]+)['\"]?\s*:\s*\[\s*([-+0-9.eE]+)\s*,\s*([-+0-9.eE]+)\s*\]"
    if path and not os.path.exists(path) and ":" in path:  # given inline: "battery: [275, 310]; radio: [250, 330]"
        entries = re.findall(entry, path)
        rest = re.sub(entry, "", path).strip(" \t;,{}")
        if not entries or rest.replace(";", "").replace(",", "").strip():
            fail(2, f"--limits '{path}': expected 'node: [min_K, max_K]' entries separated by ';' "
                    "(or the name of a file of such lines)")
    elif path:
        if not os.path.isfile(path):
            fail(2, f"{path}:0:0: limits file: {'no such file' if not os.path.exists(path) else 'not a regular file'}")
        try:
            with open(path, encoding="utf-8") as limits_file:
                content = limits_file.read()
        except (OSError, UnicodeDecodeError) as e:
            fail(2, f"{path}:0:0: limits file cannot be read as text ({e})")
        entries = re.findall(r"^\s*" + entry, content, re.M)
        if not entries:
            fail(2, f"{path}:0:0: limits file: no line 'node: [min_K, max_K]'")
    elif "/limits/node" in result.f:
        entries = zip(text(result.f["/limits/node"][()]), result.f["/limits/min"][()], result.f["/limits/max"][()])
    else:
        return {}
    for node, low, high in entries:
        if node not in result.nodes:
            fail(2, f"limits: no node '{node}' in the result")
        try:
            low, high = float(low), float(high)
        except ValueError:
            fail(2, f"limits: {node}: [{low}, {high}] are not numbers")
        if not (np.isfinite(low) and np.isfinite(high) and low < high):
            fail(2, f"limits: {node}: min {low} K is not below max {high} K")
        limits[node] = (float(low), float(high))
    return limits


def signed_off(result, limits):
    """The nodes an engineer signs off, always drawn on their own: every lumped node (the
    equipment: battery, electronics, payload) and every node with limits."""
    lumped = result.f["/nodes/lumped"][()] if "/nodes/lumped" in result.f else np.zeros(len(result.nodes), bool)
    return [i for i, name in enumerate(result.nodes) if bool(lumped[i]) or name in limits]


def colours(result, key_values, must=()):
    """One colour per node for every figure: the signed-off nodes first, then the largest by
    key up to MAX_LINES (MAX_EQUIPMENT at most when there is more equipment than that)."""
    order = [int(i) for i in must][:MAX_EQUIPMENT]
    # A large model's other nodes are its groups' bands; a few of the largest still get a line.
    others = MAX_LINES - len(order) if len(result.nodes) <= 40 else min(4, MAX_LINES - len(order))
    order += [int(i) for i in np.argsort(-key_values) if int(i) not in order][:max(0, others)]
    palette = plt.get_cmap("tab20").colors
    return {i: palette[(2 * k) % 20 if k < 10 else (2 * (k - 10) + 1) % 20] for k, i in enumerate(order)}


def shade_eclipses(ax, t, sunlit):
    """Eclipses hatched in dark blue: never the grey of a band of nodes."""
    dark = sunlit < 1.0
    for k in range(len(t) - 1):
        if dark[k] or dark[k + 1]:
            ax.axvspan(t[k], t[k + 1], facecolor="midnightblue", alpha=0.07, hatch="///", edgecolor="midnightblue",
                       lw=0, zorder=0)


def limit_marks(ax, t, temperature, shown, names, limits):
    """Each shown node's limits as dashed lines of its colour, and every position outside them
    marked with a red cross."""
    violated = False
    for i, colour in shown.items():
        if names[i] not in limits:
            continue
        lo, hi = limits[names[i]]
        ax.axhline(lo, color=colour, ls="--", lw=0.9)
        ax.axhline(hi, color=colour, ls="--", lw=0.9)
        out = (temperature[:, i] < lo) | (temperature[:, i] > hi)
        if np.any(out):
            ax.plot(t[out], temperature[out, i], "x", color="red", ms=6, mew=1.6)
            violated = True
    if violated:
        ax.plot([], [], "x", color="red", label="outside its limits")
    if any(names[i] in limits for i in shown):
        ax.plot([], [], ls="--", color="0.3", lw=0.9, label="limits (node's colour)")


def group_bands(ax, t, data, rest, names):
    """The nodes not drawn on their own: one band (min … max) per group of nodes sharing a name
    prefix, each its own colour; a small model's rest as one band."""
    if not rest:
        return
    groups = {}
    for i in rest:
        groups.setdefault(re.sub(r"\.\d+\.\d+(?=(\.back)?$)", "", names[i]) if len(names) > 40 else "other nodes",
                          []).append(i)
    if len(groups) > MAX_GROUPS:  # the largest groups by count, the others together
        keep = sorted(groups, key=lambda g: -len(groups[g]))[:MAX_GROUPS - 1]
        other = [i for g in groups if g not in keep for i in groups[g]]
        groups = {g: groups[g] for g in keep} | {"other nodes": other}
    palette = plt.get_cmap("Set2").colors
    for g, (name, members) in enumerate(groups.items()):
        ax.fill_between(t, np.nanmin(data[:, members], axis=1), np.nanmax(data[:, members], axis=1),
                        color=palette[g % len(palette)] if len(groups) > 1 else "0.6", alpha=0.35, lw=0,
                        label=f"{name} ({len(members)} nodes, range)")


def node_lines(ax, t, data, shown, names):
    for i, colour in shown.items():
        ax.plot(t, data[:, i], color=colour, lw=1.3, label=names[i])
    rest = [i for i in range(data.shape[1]) if i not in shown]
    return rest


def case_figures(result, out, shown, limits):
    f, written = result.f, []
    for k, (case, span) in enumerate(zip(result.cases, result.spans)):
        if not result.orbit or len(span) < 2:
            continue
        t = (f["/orbit/time"][()][span]) / 60.0
        sunlit = f["/orbit/sunlit_fraction"][()][span]
        breaks = np.flatnonzero(np.diff(f["/orbit/case"][()][span]) != 0) + 1
        t = np.insert(t, breaks, np.nan)
        sunlit = np.insert(sunlit, breaks, 1.0)
        stem = re.sub(r"[^\w.-]", "_", case)
        if result.thermal:
            temperature = np.insert(f["/solution/temperature"][()][span], breaks, np.nan, axis=0)
            fig, ax = plt.subplots(figsize=(10, 5.5))
            shade_eclipses(ax, t, sunlit)
            rest = node_lines(ax, t, temperature, shown, result.nodes)
            group_bands(ax, t, temperature, rest, result.nodes)
            limit_marks(ax, t, temperature, shown, result.nodes, limits)
            ax.set_ylabel("temperature [K]")
            ax.set_xlabel("time from the orbit case's start [min]  (hatched: eclipse)")
            ax.set_title(f"{result.name}, case {case}: node temperatures")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, ncol=2, loc="center left", bbox_to_anchor=(1.01, 0.5))
            fig.tight_layout()
            written.append(save(fig, out, f"{stem}_temperature.png"))
        fig, axes = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
        # Lumped nodes (equipment) absorb no environmental load: not drawn here.
        lumped = f["/nodes/lumped"][()] if "/nodes/lumped" in f else np.zeros(len(result.nodes), bool)
        surfaces = {i: c for i, c in shown.items() if not lumped[i]}
        groups = primitive_groups(result.nodes) if len(result.nodes) > 40 else None
        if groups:
            groups = {g: m for g, m in ((g, [i for i in m if not lumped[i]]) for g, m in groups.items()) if m}
        for ax, kind, label in zip(axes, ["solar", "albedo", "earth_ir"], ["direct solar", "albedo", "Earth IR"]):
            data = np.insert(f["/loads/" + kind][()][span], breaks, np.nan, axis=0)
            shade_eclipses(ax, t, sunlit)
            if groups:  # a large model: one line per primitive (its nodes summed), one colour each
                palette = plt.get_cmap("tab20").colors
                for g, (name, members) in enumerate(groups.items()):
                    ax.plot(t, data[:, members].sum(axis=1), color=palette[g % 20], lw=1.3,
                            label=f"{name} ({len(members)} nodes)")
            else:
                rest = [i for i in node_lines(ax, t, data, surfaces, result.nodes) if i < len(lumped) and not lumped[i]]
                if rest:
                    ax.plot(t, np.nansum(data[:, rest], axis=1), color="0.5", ls="--", lw=1.0,
                            label=f"{len(rest)} other nodes (sum)")
            ax.set_ylabel(f"{label} [W]")
            ax.grid(alpha=0.3)
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, fontsize=7, ncol=1, loc="center left", bbox_to_anchor=(1.0, 0.5))
        axes[-1].set_xlabel("time from the orbit case's start [min]  (hatched: eclipse)")
        fig.suptitle(f"{result.name}, case {case}: absorbed environmental power")
        fig.tight_layout()
        written.append(save(fig, out, f"{stem}_loads.png"))
    return written


def primitive_groups(nodes):
    """Nodes by primitive: a node grid's cells <primitive>.<i>.<j>[.back] grouped as
    <primitive>[.back]."""
    groups = {}
    for i, name in enumerate(nodes):
        key = re.sub(r"\.\d+\.\d+(?=(\.back)?$)", "", name)
        groups.setdefault(key, []).append(i)
    return groups


def save(fig, out, name):
    path = os.path.join(out, name)
    try:
        fig.savefig(path, dpi=110, bbox_inches="tight")
    except OSError as e:
        raise WriteFailed(f"{name}: {e}") from None
    finally:
        plt.close(fig)
    return path


def heat_flows(result):
    """Orbit-mean heat flow per case, kind and node, W (+ into the node)."""
    f = result.f
    flows = np.zeros((len(result.cases), len(KINDS), len(result.nodes)))
    for k, (span, w) in enumerate(zip(result.spans, result.weights)):
        for j, kind in enumerate(KINDS):
            if "/solution/heat/" + kind in f:
                flows[k, j] = w @ f["/solution/heat/" + kind][()][span]
    scale = np.abs(flows).max(axis=(1, 2), keepdims=True)
    flows[np.abs(flows) < 1e-12 * np.maximum(scale, 1e-300)] = 0.0  # round-off is not a heat flow
    return flows


def flow_columns(result, flows, must):
    """The bars of the heat-flow figure: every signed-off node (equipment, heaters' nodes, nodes
    with limits) on its own, then, on a large model, the other nodes summed per group (name
    prefix), else the largest other nodes, up to 20 bars. Returns (labels, (cases, kinds, bars))."""
    heated = set()
    if "/heaters/node" in result.f:
        heated = {result.nodes.index(n) for n in text(result.f["/heaters/node"][()]) if n in result.nodes}
    own = list(dict.fromkeys([*must, *sorted(heated)]))[:MAX_EQUIPMENT]
    labels, columns = [result.nodes[i] for i in own], [flows[:, :, i] for i in own]
    rest = [i for i in range(len(result.nodes)) if i not in own]
    if len(result.nodes) > 40:
        groups = {}
        for i in rest:
            groups.setdefault(re.sub(r"\.\d+\.\d+(?=(\.back)?$)", "", result.nodes[i]), []).append(i)
        for name, members in sorted(groups.items(), key=lambda g: -np.abs(flows[:, :, g[1]]).sum())[:max(1, 20 - len(own))]:
            labels.append(f"{name} ({len(members)})")
            columns.append(flows[:, :, members].sum(axis=2))
    else:
        totals = np.abs(flows[:, :, rest]).sum(axis=(0, 1))
        for j in np.argsort(-totals)[:max(0, 20 - len(own))]:
            labels.append(result.nodes[rest[j]])
            columns.append(flows[:, :, rest[j]])
    return labels, np.stack(columns, axis=2)


def heat_balance_figure(result, flows, out, must=()):
    labels, bars = flow_columns(result, flows, must)
    order = np.arange(len(labels))
    fig, axes = plt.subplots(len(result.cases), 1, figsize=(11, 3.2 * len(result.cases) + 1), squeeze=False)
    palette = plt.get_cmap("tab10").colors
    for k, ax in enumerate(axes[:, 0]):
        bottom_pos, bottom_neg = np.zeros(len(order)), np.zeros(len(order))
        for j, kind in enumerate(KINDS):
            v = bars[k, j, order]
            if not np.any(bars[:, j, order]):  # a kind some case has gets its colour in every panel
                continue
            base = np.where(v >= 0, bottom_pos, bottom_neg)
            ax.bar(range(len(order)), v, bottom=base, color=palette[j % 10], label=kind)
            bottom_pos += np.maximum(v, 0)
            bottom_neg += np.minimum(v, 0)
        ax.axhline(0, color="k", lw=0.8)
        span = max(bottom_pos.max() - bottom_neg.min(), 1e-12)  # room above and below the stacks
        ax.set_ylim(bottom_neg.min() - 0.06 * span, bottom_pos.max() + 0.06 * span)
        ax.set_xticks(range(len(order)), labels, rotation=45, ha="right", fontsize=7)
        ax.set_ylabel("orbit mean [W]")
        ax.set_title(f"case {result.cases[k]}: heat flows into (+) and out of (−) each node"
                     + (" or group (node count)" if len(result.nodes) > 40 else ""), fontsize=9)
        ax.grid(axis="y", alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=1, loc="upper left", bbox_to_anchor=(1.0, 1.0))  # clear of the bars
    fig.tight_layout()
    return save(fig, out, "heat_balance.png")


def envelope_figure(result, low, high, low_case, high_case, limits, out, must=()):
    """Every signed-off node (equipment, nodes with limits), then the hottest others, 40 in all."""
    if len(result.nodes) > 40:
        order = list(must)[:40] + [int(i) for i in np.argsort(-high) if int(i) not in must]
        order = np.array(order[:max(40, len(must[:40]))])
    else:
        order = np.arange(len(result.nodes))
    fig, ax = plt.subplots(figsize=(11, 5))
    x = np.arange(len(order))
    ax.vlines(x, low[order], high[order], color="tab:blue", lw=5, alpha=0.7, label="min … max over the design cases")
    for xi, i in zip(x, order):
        name = result.nodes[i]
        if name in limits:
            lo, hi = limits[name]
            bad = low[i] < lo or high[i] > hi
            ax.hlines([lo, hi], xi - 0.35, xi + 0.35, color="tab:red" if bad else "tab:green", lw=2)
            if high[i] > hi:  # at the end that is violated
                ax.annotate("!", (xi, high[i]), color="tab:red", ha="center", va="bottom", fontsize=12, weight="bold")
            if low[i] < lo:
                ax.annotate("!", (xi, low[i]), color="tab:red", ha="center", va="top", fontsize=12, weight="bold")
    if limits:
        ax.plot([], [], color="tab:green", lw=2, label="limits (red: violated)")
    ax.set_xticks(x, [result.nodes[i] for i in order], rotation=45, ha="right", fontsize=7)
    ax.set_ylabel("temperature [K]")
    ax.set_title(f"{result.name}: temperature envelope per node"
                 + (" (equipment, nodes with limits, then the hottest: 40 of "
                    f"{len(result.nodes)})" if len(result.nodes) > 40 else ""))
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save(fig, out, "envelope.png")


def budget_figure(result, out):
    attrs = result.f["/report"].attrs
    stages = [(k[5:-2].replace("_", " "), float(attrs[k])) for k in attrs if re.fullmatch(r"time_\w+_s", k)]
    stages = [s for s in stages if s[1] > 0]
    parts = [(p.replace("_", " "), float(attrs[f"absorbed_uncertainty_{p}_max_relative"]))
             for p in ("view_factors", "loads", "truncation") if f"absorbed_uncertainty_{p}_max_relative" in attrs]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    left.barh([s[0] for s in stages], [s[1] for s in stages], color="tab:blue")
    left.set_xlabel("wall time [s]")
    left.set_title(f"where the {sum(s[1] for s in stages):.3g} s went", fontsize=9)
    if parts:
        right.bar([p[0] for p in parts], [100 * p[1] for p in parts], color="tab:orange")
        if "accuracy" in attrs:
            right.axhline(100 * float(attrs["accuracy"]), color="tab:red", ls="--", label="accuracy asked")
            right.legend(fontsize=8)
        right.set_ylabel("1σ of a node's orbit-max absorbed power [%]")
        right.set_title("error budget: the largest share over nodes, per source", fontsize=9)
    else:
        right.text(0.5, 0.5, "no orbit loads: no absorbed-power error budget", ha="center", va="center")
        right.set_axis_off()
    fig.tight_layout()
    return save(fig, out, "budget.png")


def modes_figure(result, out):
    """The radiative network's exchange modes: the eigenvalues of G = A F the run kept, and
    how much of G they hold (Σ kept λ² / ‖G‖²_F: 1 means the truncation dropped nothing)."""
    f = result.f
    # The CSR group is there at every size (docs/hdf5-layout.md, "Matrices"); /network/conductance
    # is the (n, n) dataset up to 5,000 nodes and a link to that group beyond.
    sparse = "/network/sparse/conductance/data" in f
    if "/eigen/values" not in f or not (sparse or "/network/conductance" in f):
        return None
    values = np.sort(np.abs(f["/eigen/values"][()]))[::-1]
    if not np.any(values > 0):  # a single plate: G = 0, no exchange to show
        return None
    if sparse:
        data = f["/network/sparse/conductance/data"]
        frobenius = sum(float(np.sum(data[r:r + (1 << 20)] ** 2)) for r in range(0, data.shape[0], 1 << 20))
        nodes = int(f["/network/sparse/conductance"].attrs["shape"][0])
    else:
        g = f["/network/conductance"]
        frobenius = sum(float(np.sum(g[r:r + 512] ** 2)) for r in range(0, g.shape[0], 512))
        nodes = g.shape[0]
    held = np.cumsum(values ** 2) / frobenius
    bound = float(f["/eigen"].attrs.get("largest_dropped_eigenvalue_bound", 0.0))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    k = np.arange(1, len(values) + 1)
    left.semilogy(k, values, "o-", ms=3, label="kept modes")
    if bound > 0:
        left.axhline(bound, color="tab:red", ls="--", label="largest dropped mode (bound)")
    left.set_xlabel("exchange mode k (strongest first)")
    left.set_ylabel("|λ_k| of G = A F [m²]")
    left.set_title(f"{len(values)} of {nodes} modes kept ({f['/eigen'].attrs['method']})", fontsize=9)
    left.grid(alpha=0.3, which="both")
    left.legend(fontsize=8)
    right.semilogy(k, np.maximum(1 - held, 1e-16), color="tab:green")
    right.set_xlabel("modes kept")
    right.set_ylabel("share of ‖G‖² not held, 1 − Σλ²/‖G‖²")
    right.set_title(f"the kept modes hold {100 * held[-1]:.4g} % of G", fontsize=9)
    right.grid(alpha=0.3)
    fig.suptitle(f"{result.name}: radiative exchange modes (one eigendecomposition serves every case)")
    fig.tight_layout()
    return save(fig, out, "modes.png")


def md_table(headers, rows):
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(rows_i) + " |" for rows_i in rows]
    return "\n".join(lines) + "\n"


def write_csv(path, headers, rows):
    try:
        with open(path, "w", newline="") as out:
            w = csv.writer(out)
            w.writerow(headers)
            w.writerows(rows)
    except OSError as e:
        raise WriteFailed(f"{os.path.basename(path)}: {e}") from None


def main(f, path, out, limits_path):
    """Makes the report's files in `out` and returns their names."""
    result = Result(f)
    limits = limits_of(result, limits_path)
    md = [f"# radnet report: {result.name}\n", f"Result `{os.path.basename(path)}`: {len(result.nodes)} nodes, "
          f"{len(result.cases)} design case(s): {', '.join(result.cases)}.\n"]
    figures, temp_rows, flow_rows, heater_rows = [], [], [], []
    flows = heat_flows(result) if result.thermal else None
    key = np.abs(f["/loads/solar"][()]).max(axis=0) if result.orbit else np.zeros(len(result.nodes))
    if result.thermal:
        key = np.pad(key, (0, len(result.nodes) - len(key))) + f["/solution/temperature"][()].max(axis=0) * 1e-9
    shown = colours(result, key, signed_off(result, limits))
    md.append("Drawn on their own in the figures (equipment and nodes with limits first): "
              + ", ".join(result.nodes[i] for i in shown) + ".\n")
    for k, (case, span, w) in enumerate(zip(result.cases, result.spans, result.weights)):
        md.append(f"\n## Case {case}\n")
        if not result.thermal:
            continue
        t = f["/solution/temperature"][()][span]
        rows = [(result.nodes[i], f"{t[:, i].min():.2f}", f"{w @ t[:, i]:.2f}", f"{t[:, i].max():.2f}")
                for i in range(len(result.nodes))]
        temp_rows += [(case, *r) for r in rows]
        md.append("Temperatures, K (minimum, time-weighted mean, maximum over the case's positions):\n\n")
        md.append(md_table(["node", "min", "mean", "max"], rows))
        frows = [(result.nodes[i], *[f"{flows[k, j, i]:.4g}" for j in range(len(KINDS))])
                 for i in range(len(result.nodes))]
        flow_rows += [(case, *r) for r in frows]
        md.append("\nHeat flows, W (orbit mean, + into the node):\n\n")
        md.append(md_table(["node", *KINDS], frows))
        if "/heaters/name" in f:
            names, node = text(f["/heaters/name"][()]), text(f["/heaters/node"][()])
            power = f["/heaters/power"][()][span]
            duty = f["/heaters/case_duty"][()] if "/heaters/case_duty" in f else None
            starts = f["/cases/orbit_case_start"][()] if "/cases/orbit_case_start" in f else None
            rows = slice(starts[k], starts[k + 1]) if starts is not None else slice(0, None)
            rated = f["/heaters/rated_power"][()] if "/heaters/rated_power" in f else None

            def heater_row(h, n):
                # As the console: the duty is the largest of the case's orbit cases, the mean power
                # duty × the heater's power (its time on, not its samples at the positions).
                on = duty[rows, h].max() if duty is not None else None
                mean_w = on * rated[h] if on is not None and rated is not None else w @ power[:, h]
                return n, node[h], f"{100 * (on if on is not None else 0):.1f} %", f"{mean_w:.4g}"
            hrows = [heater_row(h, n) for h, n in enumerate(names)]
            heater_rows += [(case, *r) for r in hrows]
            md.append("\nHeaters:\n\n" + md_table(["heater", "node", "duty", "mean power W"], hrows))
    if result.thermal:
        if "/solution/envelope/temperature_max" in f:
            low, high = f["/solution/envelope/temperature_min"][()], f["/solution/envelope/temperature_max"][()]
            low_case = [result.cases[c] for c in f["/solution/envelope/temperature_min_case"][()]]
            high_case = [result.cases[c] for c in f["/solution/envelope/temperature_max_case"][()]]
        else:
            temperature = f["/solution/temperature"][()]
            low, high = temperature.min(axis=0), temperature.max(axis=0)
            low_case = high_case = [result.cases[0]] * len(result.nodes)
        env_rows, violations = [], 0
        for i, name in enumerate(result.nodes):
            row = [name, f"{low[i]:.2f}", low_case[i], f"{high[i]:.2f}", high_case[i]]
            if limits:
                lo, hi = limits.get(name, (None, None))
                if lo is not None:
                    margin = min(low[i] - lo, hi - high[i])
                    ok = margin >= 0
                    violations += not ok
                    row += [f"{lo:.2f}", f"{hi:.2f}", f"{margin:.2f}", "yes" if ok else "**NO**"]
                else:
                    row += ["", "", "", ""]
            env_rows.append(row)
        head = ["node", "min K", "min case", "max K", "max case"] + (
            ["limit min K", "limit max K", "margin K", "within"] if limits else [])
        md.append("\n## Envelope over the design cases\n\n")
        if limits:
            md.append(f"{violations} node(s) outside their limits.\n\n")
        md.append(md_table(head, env_rows))
        write_csv(os.path.join(out, "envelope.csv"), [h.replace(" ", "_") for h in head],
                  [[c.replace("**", "") for c in r] for r in env_rows])
        write_csv(os.path.join(out, "temperatures.csv"), ["case", "node", "min_K", "mean_K", "max_K"], temp_rows)
        write_csv(os.path.join(out, "heat_flows.csv"), ["case", "node", *[k + "_W" for k in KINDS]], flow_rows)
        write_csv(os.path.join(out, "heaters.csv"), ["case", "heater", "node", "duty", "mean_W"], heater_rows)
        must = signed_off(result, limits)
        figures.append(heat_balance_figure(result, flows, out, must))
        figures.append(envelope_figure(result, low, high, low_case, high_case, limits, out, must))
    figures += case_figures(result, out, shown, limits)
    figures.append(budget_figure(result, out))
    modes = modes_figure(result, out)
    if modes:
        figures.append(modes)
    md.append("\n## Speed and error\n\n")
    attrs = f["/report"].attrs
    for key_name, label in (("absorbed_uncertainty_max_relative", "largest 1σ of absorbed power (share of orbit max)"),
                            ("accuracy", "accuracy asked"), ("view_factor_error", "largest σ of a view factor"),
                            ("heat_balance_max_imbalance_w", "largest heat-balance imbalance, W")):
        if key_name in attrs:
            md.append(f"- {label}: {float(attrs[key_name]):.3g}\n")
    stages = [(k[5:-2].replace("_", " "), float(attrs[k])) for k in attrs if re.fullmatch(r"time_\w+_s", k)]
    if stages:  # the times the budget figure draws, as numbers
        md.append("\nTime per stage, s (the run's wall clock on its machine):\n\n")
        md.append(md_table(["stage", "s"], [(name, f"{seconds:.3g}") for name, seconds in stages if seconds > 0]))
    if "/report/warnings" in f:
        warnings = text(f["/report/warnings"][()])
        md.append(f"\n## Warnings of the run ({len(warnings)})\n\n")
        md.append("".join(f"- {w}\n" for w in warnings) if warnings else "None.\n")
    md.append("\n## Figures\n\n" + "".join(f"![{os.path.basename(p)}]({os.path.basename(p)})\n" for p in figures))
    try:
        with open(os.path.join(out, "report.md"), "w") as report:
            report.write("".join(md))
    except OSError as e:
        raise WriteFailed(f"report.md: {e}") from None
    return ["report.md", *[os.path.basename(p) for p in figures]]


def scratch_folder(out):
    """A new folder beside OUTDIR for the report's files while they are made."""
    parent = os.path.dirname(os.path.abspath(out))
    for attempt in range(100):
        temp = os.path.join(parent, f".{os.path.basename(os.path.abspath(out))}.tmp-{os.getpid()}-{attempt}")
        try:
            os.mkdir(temp)
            return temp
        except FileExistsError:
            continue
    raise WriteFailed(f"no free temporary name beside {out}")


def publish(temp, out):
    """Moves every file made into OUTDIR (replacing the earlier report's files of the same
    names, never touching others), with termination signals held until all are in place."""
    held = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT}
    signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        os.makedirs(out, exist_ok=True)
        for name in sorted(os.listdir(temp)):
            os.replace(os.path.join(temp, name), os.path.join(out, name))
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, held)


def interrupted(signum, frame):
    raise KeyboardInterrupt


def run(path, out, limits_path):
    """main() with every error mapped to radnet's exit codes: no traceback reaches the user."""
    if not os.path.isfile(path):
        fail(2, f"{path}:0:0: {'no such file' if not os.path.exists(path) else 'not a regular file'}")
    if os.path.lexists(out) and not os.path.isdir(out):
        fail(2, f"{out}: exists and is not a directory")
    temp = None
    try:
        try:
            f = h5py.File(path, "r")
        except OSError as e:
            fail(2, f"{path}: not an HDF5 file ({e})")
        if "/meta" not in f or "/nodes/name" not in f:
            fail(2, f"{path}: not a radnet result (no /meta or /nodes/name)")
        check_result(f, path)
        try:
            temp = scratch_folder(out)
        except OSError as e:
            raise WriteFailed(f"cannot create a folder beside {out}: {e}") from None
        made = main(f, path, temp, limits_path)
        try:
            publish(temp, out)
        except OSError as e:
            raise WriteFailed(f"cannot move the report into {out}: {e}") from None
        for name in made:
            print(os.path.join(out, name))
        return 0
    except Malformed as e:
        fail(2, f"{path}: malformed result: {e}")
    except WriteFailed as e:
        fail(4, f"report not written: {e}")
    except KeyboardInterrupt:
        return 130
    except Exception as e:  # anything else the file's content provoked: named, never a traceback
        fail(2, f"{path}: malformed result ({type(e).__name__}: {e})")
    finally:
        if temp is not None:
            shutil.rmtree(temp, ignore_errors=True)


if __name__ == "__main__":
    args = sys.argv[1:]
    limits_file = None
    if "--limits" in args:
        at = args.index("--limits")
        limits_file = args[at + 1]
        del args[at:at + 2]
    if len(args) != 2:
        fail(2, "usage: radnet_report.py RESULT.h5 OUTDIR [--limits FILE.yaml]")
    signal.signal(signal.SIGTERM, interrupted)  # ends as Ctrl-C does: the scratch folder removed
    sys.exit(run(args[0], args[1], limits_file))
