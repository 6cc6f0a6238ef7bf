#!/usr/bin/python3
"""Runs every ```sh block of docs/tutorial.md in order, in an empty directory, with
`radnet` the built binary; fails on the first command that fails, and checks that the files
the tutorial promises exist.

usage: run_tutorial.py RADNET SOURCE_DIR WORK_DIR
"""
import os
import re
import shutil
import subprocess
import sys

radnet, source, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
tutorial = open(os.path.join(source, "docs/tutorial.md")).read()
blocks = re.findall(r"```sh\n(.*?)```", tutorial, re.S)
bin_dir = os.path.join(work, ".bin")
os.makedirs(bin_dir)
os.symlink(os.path.abspath(radnet), os.path.join(bin_dir, "radnet"))
env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ["PATH"])
for k, block in enumerate(blocks):
    run = subprocess.run(["bash", "-euo", "pipefail", "-c", block], cwd=work, env=env, capture_output=True, text=True)
    print(f"--- block {k + 1}: exit {run.returncode}\n{run.stdout[-1500:]}{run.stderr[-1500:]}")
    if run.returncode != 0:
        sys.exit(1)
for name in ("sat.h5", "sat.xmf", "sat.hot.xmf", "sat.cold.xmf", "sat-report/report.md", "sat-report/envelope.png",
             "sat-hot.d", "sat-hot.sin", "sat-cold-csv/nodes.csv"):
    if not os.path.exists(os.path.join(work, name)):
        print("FAIL: the tutorial promises", name)
        sys.exit(1)
print(f"{len(blocks)} blocks ran")
