#!/usr/bin/python3
"""`radnet report` on the hot/cold CubeSat (design cases, heaters, transient) with limits.

usage: check_report.py RADNET SOURCE_DIR WORK_DIR

Checks: every table and figure is written; the report's time-weighted mean temperature of
each case and node (computed in docs/radnet_report.py from /solution/temperature) equals
radnet's own /solution/case_temperature_mean (computed in C++ from the temperatures and
/cases/time_weight, which the report uses), and min and max equal
/solution/case_temperature_min/_max, each to the 0.01 K printed (5e-3 K); the envelope
flags exactly the nodes whose limits the run violates; bad input exits 2.
"""
import csv
import os
import subprocess
import sys

import h5py
import numpy as np

radnet, source, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
failures = []
h5 = os.path.join(work, "hc.h5")
console = subprocess.run([radnet, "run", os.path.join(source, "cases/examples/cubesat-hot-cold.yaml"), "-o", h5, "-q"],
                         check=True, capture_output=True, text=True).stdout


def console_means(text, section):
    """{case: {node: mean}} of the console's tables that follow a line starting with `section`."""
    out, case, table = {}, None, False
    for line in text.splitlines():
        if line.startswith("case ") and "(optics" in line:
            case = line.split()[1]
        elif line.startswith(section):
            table = True
        elif table and line.startswith("node"):
            column = line.split().index("mean")
        elif table and line and not line[0].isspace() and len(line.split()) > column:
            try:
                out.setdefault(case, {})[line.split()[0]] = float(line.split()[column])
            except ValueError:
                table = False
        else:
            table = False
    return out
limits = os.path.join(work, "limits.yaml")
open(limits, "w").write("panel_py: [233.15, 343.15]\nbattery: [273.15, 318.15]\nbus.+x: [200.0, 400.0]\n")
out = os.path.join(work, "report")
run = subprocess.run([radnet, "report", h5, "-o", out, "--limits", limits], capture_output=True, text=True)
if run.returncode != 0:
    failures.append(f"radnet report exited {run.returncode}: {run.stderr}")
for name in ("report.md", "temperatures.csv", "heat_flows.csv", "heaters.csv", "envelope.csv", "heat_balance.png",
             "envelope.png", "hot_temperature.png", "cold_temperature.png", "hot_loads.png", "budget.png", "modes.png"):
    if not os.path.getsize(os.path.join(out, name)) > 0:
        failures.append(f"{name} missing or empty")
with h5py.File(h5) as f:
    cases = [c.decode() for c in f["cases/name"][()]]
    nodes = [n.decode() for n in f["nodes/name"][()]]
    mean, low, high = (f[f"solution/case_temperature_{k}"][()] for k in ("mean", "min", "max"))
    envelope = f["solution/envelope/temperature_min"][()], f["solution/envelope/temperature_max"][()]
rows = list(csv.DictReader(open(os.path.join(out, "temperatures.csv"))))
if len(rows) != len(cases) * len(nodes):
    failures.append(f"temperatures.csv has {len(rows)} rows, expected {len(cases) * len(nodes)}")
for row in rows:
    k, i = cases.index(row["case"]), nodes.index(row["node"])
    if abs(float(row["mean_K"]) - mean[k, i]) > 5e-3 + 1e-9:  # printed to 0.01 K
        failures.append(f"{row['case']} {row['node']}: mean {row['mean_K']} K, radnet {mean[k, i]:.6f} K")
    if abs(float(row["min_K"]) - low[k, i]) > 5e-3 or abs(float(row["max_K"]) - high[k, i]) > 5e-3:
        failures.append(f"{row['case']} {row['node']}: min/max differ from radnet's")
# One orbit mean everywhere (time-weighted): the console's temperature and absorbed-power
# means equal /solution/case_temperature_mean and /cases/time_weight · /loads to their printed
# digits (0.01 K; 5 significant digits of W), and `expect: orbit_mean_absorbed` with `case:`
# equals the latter to 1e-9 W.
with h5py.File(h5) as f:
    start, weight = f["cases/position_start"][()], f["cases/time_weight"][()]
    absorbed = f["loads/solar"][()] + f["loads/albedo"][()] + f["loads/earth_ir"][()]
temperature_means, absorbed_means = console_means(console, "temperatures, K"), console_means(console, "orbit:")
for k, case in enumerate(cases):
    span = slice(start[k], start[k + 1])
    for node, value in temperature_means.get(case, {}).items():
        if abs(value - mean[k, nodes.index(node)]) > 5e-3 + 1e-9:
            failures.append(f"console {case} {node}: mean {value} K, /solution/case_temperature_mean {mean[k, nodes.index(node)]}")
    for node, value in absorbed_means.get(case, {}).items():
        exact = absorbed[span, nodes.index(node)] @ weight[span]
        if abs(value - exact) > 5e-5 * max(1.0, abs(exact)):
            failures.append(f"console {case} {node}: mean absorbed {value} W, time-weighted {exact} W")
# The figures draw every lumped node (equipment) and every node with limits on its own.
with h5py.File(h5) as f:
    lumped = [n for n, l in zip(nodes, f["nodes/lumped"][()]) if l]
drawn = next(line for line in open(os.path.join(out, "report.md")) if line.startswith("Drawn on their own"))
drawn = [n.strip() for n in drawn.split(": ", 1)[1].rstrip(".\n").split(",")]
for name in lumped + ["panel_py", "battery", "bus.+x"]:
    if name not in drawn:
        failures.append(f"{name} (equipment or with limits) is not drawn on its own: {drawn}")
# Heaters: the report's and the console's mean power are duty × rated power, as its duty says.
with h5py.File(h5) as f:
    rated, case_duty, orbit_start = f["heaters/rated_power"][()], f["heaters/case_duty"][()], f["cases/orbit_case_start"][()]
for row in csv.DictReader(open(os.path.join(out, "heaters.csv"))):
    k = cases.index(row["case"])
    on = case_duty[orbit_start[k]:orbit_start[k + 1], 0].max()
    if abs(float(row["duty"].rstrip(" %")) - 100 * on) > 0.05 or abs(float(row["mean_W"]) - on * rated[0]) > 5e-4 * rated[0]:
        failures.append(f"heaters.csv {row}: duty {100 * on:.2f} % of {rated[0]} W expected")
for line in console.splitlines():
    if line.startswith("heater "):
        on, mean_w = float(line.split("duty ")[1].split(" %")[0]) / 100, float(line.split("mean power ")[1].split(" W")[0])
        if abs(mean_w - on * rated[0]) > 5e-4 * rated[0]:
            failures.append(f"console '{line}': mean power is not duty × {rated[0]} W")
print(f"console means compared: {sum(map(len, temperature_means.values()))} temperatures, {sum(map(len, absorbed_means.values()))} absorbed powers")
if len(temperature_means) != len(cases) or len(absorbed_means) != len(cases):
    failures.append(f"console tables not found: {list(temperature_means)} {list(absorbed_means)}")
i = nodes.index("bus.+y")
checked = os.path.join(work, "expect.yaml")
with open(os.path.join(source, "cases/examples/cubesat-hot-cold.yaml")) as f:
    text = f.read()
text = text.replace("samples: 64", "samples: 2")
expectations = "".join(f"  - {{quantity: orbit_mean_absorbed, node: bus.+y, case: {c}, value: {absorbed[start[k]:start[k + 1], i] @ weight[start[k]:start[k + 1]]!r}, tolerance: 1.0e-9}}\n"
                       for k, c in enumerate(cases))
open(checked, "w").write(text + "expect:\n" + expectations)
run = subprocess.run([radnet, "check", checked], capture_output=True, text=True, cwd=os.path.join(source, "cases/examples"))
if run.returncode != 0:
    failures.append(f"expect orbit_mean_absorbed with case: {run.stdout} {run.stderr}")
expected = {"panel_py": envelope[0][nodes.index("panel_py")] < 233.15 or envelope[1][nodes.index("panel_py")] > 343.15,
            "battery": envelope[0][nodes.index("battery")] < 273.15 or envelope[1][nodes.index("battery")] > 318.15,
            "bus.+x": False}
for row in csv.DictReader(open(os.path.join(out, "envelope.csv"))):
    if row["node"] in expected and (row["within"] == "NO") != expected[row["node"]]:
        failures.append(f"envelope: {row['node']} flagged {row['within']}, expected violated={expected[row['node']]}")
if not any(expected.values()):
    failures.append("the limits chosen violate nothing: the test would not see a missing flag")
# The same limits given inline flag the same nodes; malformed inline limits exit 2, no traceback.
inline = "panel_py: [233.15, 343.15]; battery: [273.15, 318.15]; bus.+x: [200.0, 400.0]"
run = subprocess.run([radnet, "report", h5, "-o", out + "-inline", "--limits", inline], capture_output=True, text=True)
if run.returncode != 0 or open(os.path.join(out + "-inline", "envelope.csv")).read() != \
        open(os.path.join(out, "envelope.csv")).read():
    failures.append(f"inline --limits: exit {run.returncode} or another envelope: {run.stderr}")
for bad in ("battery: [318.15, 273.15]", "battery: 273..318", "nosuch: [1, 2]"):
    run = subprocess.run([radnet, "report", h5, "-o", out + "-bad", "--limits", bad], capture_output=True, text=True)
    if run.returncode != 2 or "Traceback" in run.stderr or os.path.exists(out + "-bad"):
        failures.append(f"--limits '{bad}': exit {run.returncode}, expected 2 with a message: {run.stderr}")
run = subprocess.run([radnet, "report", limits], capture_output=True, text=True)
if run.returncode != 2:
    failures.append(f"a YAML file as the result: exit {run.returncode}, expected 2")
for f in failures:
    print("FAIL:", f)
print(f"report checked, {len(failures)} failure(s)")
sys.exit(1 if failures else 0)
