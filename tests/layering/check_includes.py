#!/usr/bin/env python3
"""Includes point down (ARCHITECTURE.md): checks every #include "..." of the
magenc sources against the layer order

    apps/, studies/          executables: may include anything below
    src/report/              study output folder, summaries, standard figures
    src/analysis/, field_solver/   computation on top of the probe pipeline; the FEM library
    src/io/                  tables, plots, VTK paths
    src/probe/               mounting, arrays, angle error, spectrum
    src/fields/              field sources (exact, grid, magnet)
    src/core/                errors, units, formatting, configuration

A file may include headers of its own layer or of a lower one, never of a
higher one. Two extra rules keep the link order of the libraries: src/ (the
magenc library) never includes field_solver/ (magenc_fem links magenc, not the
other way round). probe/ sits above fields/: a probe samples a field source,
a field source knows no probe.

Include resolution: "dir/name.hpp" is src/dir/name.hpp; a bare "name.hpp" is
the including file's folder first, then field_solver/ (the FEM library's
include directory); magenc_version.hpp is generated from
src/core/version.hpp.in. An include that resolves to none of these is reported
too (a typo or a file outside the layers).

    check_includes.py [ROOT]        ROOT: the repository (default: two levels up)
    check_includes.py --self-test   runs the checker on synthetic trees in a temp
                                    dir: a clean one must pass, violating ones fail

Exit 0 when clean; 1 with one line per offending include otherwise.
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from checker_selftest import repo_root, run_self_test  # noqa: E402 (tests/checker_selftest.py)

# Rank of each layer; an include must not go to a higher rank.
RANK = {
    "core": 0,
    "fields": 1,
    "probe": 2,
    "io": 3,
    "analysis": 4,
    "field_solver": 4,
    "report": 5,
    "apps": 6,
    "studies": 6,
}
SCANNED = ["src", "field_solver", "apps", "studies"]
SOURCE_EXT = (".hpp", ".cpp", ".h", ".cc", ".hpp.in")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
GENERATED = {"magenc_version.hpp": "core"}


def layer_of(root, path):
    """Layer name of a file path (absolute) inside root, or None."""
    rel = os.path.relpath(path, root).split(os.sep)
    if rel[0] == "src" and len(rel) > 2:
        return rel[1]
    if rel[0] in ("field_solver", "apps", "studies"):
        return rel[0]
    return None


def resolve(root, including, name):
    """Layer of the included header, or None when it resolves nowhere."""
    if name in GENERATED:
        return GENERATED[name]
    if "/" in name:
        target = os.path.join(root, "src", name)
        if os.path.isfile(target):
            return layer_of(root, target)
        return None
    for folder in (os.path.dirname(including), os.path.join(root, "field_solver")):
        target = os.path.join(folder, name)
        if os.path.isfile(target):
            return layer_of(root, target)
    return None


def check(root):
    """List of violation messages for the tree at root."""
    problems = []
    for top in SCANNED:
        base = os.path.join(root, top)
        for dirpath, _, files in sorted(os.walk(base)):
            for f in sorted(files):
                if not f.endswith(SOURCE_EXT):
                    continue
                path = os.path.join(dirpath, f)
                rel = os.path.relpath(path, root)
                src_layer = layer_of(root, path)
                if src_layer not in RANK:
                    problems.append(f"{rel}: file outside the known layers ({', '.join(sorted(RANK))})")
                    continue
                with open(path, encoding="utf-8", errors="replace") as fh:
                    for lineno, line in enumerate(fh, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        name = m.group(1)
                        where = f'{rel}:{lineno}: #include "{name}"'
                        dst_layer = resolve(root, path, name)
                        if dst_layer is None:
                            problems.append(f"{where}: resolves to no file of src/, field_solver/ or the file's folder")
                        elif dst_layer not in RANK:
                            problems.append(f"{where}: includes a file outside the known layers")
                        elif RANK[dst_layer] > RANK[src_layer]:
                            problems.append(f"{where}: {src_layer} (layer {RANK[src_layer]}) includes "
                                            f"{dst_layer} (layer {RANK[dst_layer]}): includes must point down")
                        elif rel.startswith("src" + os.sep) and dst_layer == "field_solver":
                            problems.append(f"{where}: src/ (library magenc) includes field_solver/ "
                                            "(magenc_fem links magenc, not the reverse)")
    return problems


def self_test():
    """The checker must pass a clean tree and name each kind of violation."""
    clean = {
        "src/core/errors.hpp": "#pragma once\n",
        "src/core/config.hpp": '#include "core/errors.hpp"\n',
        "src/fields/magnet.hpp": '#include "core/config.hpp"\n',
        "src/probe/mounting.hpp": '#include "fields/magnet.hpp"\n',
        "src/io/tables.hpp": '#include "probe/mounting.hpp"\n#include <vector>\n',
        "src/analysis/sweep.hpp": '#include "io/tables.hpp"\n',
        "src/report/study_output.hpp": '#include "analysis/sweep.hpp"\n#include "magenc_version.hpp"\n',
        "field_solver/mesh.hpp": '#include "analysis/sweep.hpp"\n',
        "field_solver/mesh.cpp": '#include "mesh.hpp"\n',
        "studies/s.cpp": '#include "report/study_output.hpp"\n#include "mesh.hpp"\n',
        "apps/a.cpp": '#include "report/study_output.hpp"\n',
    }
    violating = {
        "analysis includes report": ("src/analysis/bad.cpp", '#include "report/study_output.hpp"\n',
                                     "analysis (layer 4) includes report (layer 5)"),
        "field_solver includes report": ("field_solver/bad.cpp", '  #  include "report/study_output.hpp"\n',
                                         "field_solver (layer 4) includes report (layer 5)"),
        "core includes fields": ("src/core/bad.hpp", '#include "fields/magnet.hpp"\n',
                                 "core (layer 0) includes fields (layer 1)"),
        "fields includes probe": ("src/fields/bad.cpp", '#include "probe/mounting.hpp"\n',
                                  "fields (layer 1) includes probe (layer 2)"),
        "src includes field_solver": ("src/report/bad.cpp", '#include "mesh.hpp"\n',
                                      "src/ (library magenc) includes field_solver/"),
        "analysis includes field_solver": ("src/analysis/bad2.cpp", '#include "../../field_solver/mesh.hpp"\n',
                                           "resolves to no file"),
        "unknown header": ("src/io/bad.cpp", '#include "io/missing.hpp"\n', "resolves to no file"),
    }

    def clean_failure(root):
        problems = check(root)
        return "the clean tree is reported:\n  " + "\n  ".join(problems) if problems else None

    return run_self_test(check, clean, violating, clean_failure, at=lambda rel: rel + ":1:")


def main(argv):
    if len(argv) > 1 and argv[1] == "--self-test":
        return self_test()
    root = repo_root(argv, __file__)
    problems = check(root)
    for p in problems:
        print(p)
    n = sum(1 for top in SCANNED for _, _, fs in os.walk(os.path.join(root, top)) for f in fs if f.endswith(SOURCE_EXT))
    if problems:
        print(f"check_includes: {len(problems)} include(s) point up or nowhere ({n} files checked)")
        return 1
    print(f"check_includes: {n} files, every include points down")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
