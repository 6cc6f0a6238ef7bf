#!/usr/bin/env python3
"""The layout of the source tree, as docs/design.md states it ("Folders and what each may
include"): which folder may include which, how many sources stay loose beside the role
folders, and how long a source file may grow. Exits 1 naming every rule that is broken.

    check_layout.py SOURCE_DIR
"""
import pathlib
import re
import sys

# Project includes each folder may use (prefixes of the quoted include path). A file's own
# folder is always allowed. Order: the most specific folder first.
ALLOWED_PROJECT = [
    ("geometry/scene/", ["geometry/scene/", "solver/units.hpp"]),
    ("geometry/rays/", ["geometry/rays/", "geometry/scene/", "geometry/reciprocity.hpp", "solver/units.hpp"]),
    ("geometry/exact/", ["geometry/exact/", "geometry/scene/", "geometry/reciprocity.hpp", "solver/units.hpp"]),
    ("geometry/correction/", ["geometry/correction/", "geometry/reciprocity.hpp", "solver/units.hpp",
                              "solver/parallel.hpp"]),
    ("geometry/irradiance/", ["geometry/irradiance/", "geometry/rays/", "geometry/scene/", "solver/units.hpp"]),
    ("geometry/", ["geometry/reciprocity.hpp", "solver/units.hpp", "solver/parallel.hpp"]),
    ("solver/radiative/", ["solver/radiative/", "solver/units.hpp", "solver/status.hpp", "solver/parallel.hpp"]),
    ("solver/thermal/", ["solver/thermal/", "solver/units.hpp", "solver/status.hpp", "solver/parallel.hpp"]),
    ("solver/", ["solver/units.hpp", "solver/status.hpp", "solver/parallel.hpp"]),
    ("orbits/", ["orbits/", "geometry/", "solver/units.hpp"]),
    ("cases/cluster/", ["cases/cluster/"]),
    ("cases/config/", ["cases/config/", "solver/", "geometry/", "orbits/"]),
    ("cases/pipeline/", ["cases/pipeline/", "cases/config/", "cases/cluster/", "solver/", "geometry/", "orbits/"]),
    ("cases/output/", ["cases/output/", "cases/pipeline/", "cases/config/", "cases/cluster/", "solver/",
                       "geometry/", "orbits/"]),
    ("cases/cli/", ["cases/"]),
]
# Third-party headers a folder must never include (the one-way rules between stages).
FORBIDDEN_SYSTEM = [
    ("solver/", ["CGAL/", "yaml-cpp/", "GeographicLib/", "hdf5", "H5", "mpi.h"]),
    ("geometry/", ["yaml-cpp/", "GeographicLib/", "hdf5", "H5", "mpi.h"]),
    ("orbits/", ["yaml-cpp/", "hdf5", "H5", "mpi.h"]),
]
# Folders split into roles keep at most this many sources loose beside their role folders.
ROLE_SPLIT = {"geometry": 3, "solver": 3}
MAX_LINES = 400
SOURCES = ("*.cpp", "*.hpp")


def rule_for(table, rel):
    for prefix, value in table:
        if rel.startswith(prefix):
            return prefix, value
    return None, None


def main(top):
    top = pathlib.Path(top)
    problems = []
    files = [p for folder in ("geometry", "solver", "orbits", "cases") for pattern in SOURCES
             for p in (top / folder).rglob(pattern)]
    if len(files) < 50:
        problems.append(f"only {len(files)} sources found under {top}: wrong SOURCE_DIR?")
    for path in sorted(files):
        rel = path.relative_to(top).as_posix()
        text = path.read_text(encoding="utf-8")
        lines = text.count("\n")
        if lines > MAX_LINES:
            problems.append(f"{rel}: {lines} lines (at most {MAX_LINES})")
        own, allowed = rule_for(ALLOWED_PROJECT, rel)
        _, forbidden = rule_for(FORBIDDEN_SYSTEM, rel)
        for number, line in enumerate(text.split("\n"), 1):
            m = re.match(r'\s*#\s*include\s*([<"])([^">]+)[">]', line)
            if not m:
                continue
            name = m.group(2)
            if m.group(1) == '"':
                if not (top / name).is_file():
                    problems.append(f"{rel}:{number}: includes \"{name}\", which is no file of the project")
                elif allowed is not None and not any(name.startswith(a) for a in allowed):
                    problems.append(f"{rel}:{number}: {own} may not include \"{name}\"")
            elif forbidden and any(name.startswith(f) for f in forbidden):
                problems.append(f"{rel}:{number}: {rel.split('/')[0]}/ may not include <{name}>")
    for folder, most in ROLE_SPLIT.items():
        loose = sorted(p.name for pattern in SOURCES for p in (top / folder).glob(pattern))
        roles = sorted(p.name for p in (top / folder).iterdir() if p.is_dir())
        if len(loose) > most:
            problems.append(f"{folder}/: {len(loose)} loose sources ({', '.join(loose)}); at most {most}")
        design = (top / "docs" / "design.md").read_text(encoding="utf-8")
        for role in roles:
            if f"`{folder}/{role}/`" not in design:
                problems.append(f"{folder}/{role}/ is not named in docs/design.md's folder table")
    for p in problems:
        print(p)
    print(f"{len(files)} sources checked, {len(problems)} layout problems")
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
