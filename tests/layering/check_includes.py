#!/usr/bin/env python3
"""The house rules of ARCHITECTURE.md, checked on every #include "..." of the
magenc sources. The layers, lowest first:

    src/core/                errors, units, formatting, configuration
    src/fields/              field sources (exact, grid, magnet)
    src/probe/               mounting, arrays, angle error, spectrum
    src/io/                  tables, plots, VTK paths
    field_solver/            the FEM library (mesh/, fe/, solve/, field_io/)
    src/analysis/            engines that two or more studies or tools share
    src/report/              study output folder, standard figures, shared reports
    apps/, studies/, python/ the tools, one folder per study, the Python module

Rules (each broken one is one line):
1. includes point down: a file includes headers of its own layer or a lower one;
2. a study is one room: studies/<a>/ never includes studies/<b>/, and the tools
   (apps/, python/) never include a study;
3. the shared layers hold only shared code: every unit (x.hpp with its x.cpp) of
   src/analysis/ and src/report/ is reached, through includes, by at least two
   clients (a study folder, a tool of apps/, the Python module); one that serves
   a single study belongs in that study's folder;
   inside field_solver/, its parts are layered too: mesh < fe < solve < field_io;
4. no cycle: no unit reaches itself through includes (a unit is x.hpp + x.cpp);
5. every include resolves: "dir/name.hpp" is src/dir/name.hpp, or the file at
   the repository root for "field_solver/..." and "studies/..."; a bare
   "name.hpp" is the including file's folder; magenc_version.hpp is generated
   from src/core/version.hpp.in.

    check_includes.py [ROOT]        ROOT: the repository (default: two levels up)
    check_includes.py --self-test   runs the checker on synthetic trees in a temp
                                    dir: a clean one must pass, violating ones fail
    check_includes.py --stats [ROOT] files and lines per layer, includes up, cycles

Exit 0 when clean; 1 with one line per problem otherwise.
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
    "field_solver": 4,
    "analysis": 5,
    "report": 6,
    "apps": 7,
    "studies": 7,
    "python": 7,
}
SHARED = ("analysis", "report")
# The FEM library's parts, lowest first: an include inside field_solver/ must not go to a higher part.
FEM_PARTS = {"mesh": 0, "fe": 1, "solve": 2, "field_io": 3}
SCANNED = ["src", "field_solver", "apps", "studies", "python"]
SOURCE_EXT = (".hpp", ".cpp", ".h", ".cc", ".hpp.in")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
GENERATED = {"magenc_version.hpp": "core"}


def layer_of(root, path):
    """Layer name of a file path (absolute) inside root, or None."""
    rel = os.path.relpath(path, root).split(os.sep)
    if rel[0] == "src" and len(rel) > 2:
        return rel[1]
    if rel[0] in ("field_solver", "apps", "studies", "python"):
        return rel[0]
    return None


def client_of(root, path):
    """The client a file belongs to: 'studies/<name>', 'apps/<file stem>', 'python'; None for the libraries."""
    rel = os.path.relpath(path, root).split(os.sep)
    if rel[0] == "studies" and len(rel) > 2:
        return "studies/" + rel[1]
    if rel[0] == "apps":
        return "apps/" + os.path.splitext(rel[-1])[0]
    if rel[0] == "python":
        return "python"
    return None


def fem_part(root, path):
    """The part of field_solver/ a file lives in (mesh, fe, solve, field_io), or None."""
    rel = os.path.relpath(path, root).split(os.sep)
    return rel[1] if rel[0] == "field_solver" and len(rel) > 2 else None


def unit_of(root, path):
    """x.hpp and x.cpp of one folder are one unit: the path without its extension, relative to root."""
    rel = os.path.relpath(path, root)
    for ext in SOURCE_EXT:
        if rel.endswith(ext):
            return rel[: -len(ext)]
    return rel


def resolve(root, including, name):
    """Absolute path of the included file, 'generated' for magenc_version.hpp, or None when it resolves nowhere."""
    if name in GENERATED:
        return "generated"
    if "/" in name:
        top = name.split("/")[0]
        target = os.path.join(root, name) if top in ("field_solver", "studies") else os.path.join(root, "src", name)
    else:
        target = os.path.join(os.path.dirname(including), name)
    return target if os.path.isfile(target) else None


def scan(root):
    """(files, edges): every scanned source file, and (file, line number, include text, resolved path) per include."""
    files, edges = [], []
    for top in SCANNED:
        for dirpath, _, names in sorted(os.walk(os.path.join(root, top))):
            for f in sorted(names):
                if not f.endswith(SOURCE_EXT):
                    continue
                path = os.path.join(dirpath, f)
                files.append(path)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    for lineno, line in enumerate(fh, 1):
                        m = INCLUDE.match(line)
                        if m:
                            edges.append((path, lineno, m.group(1), resolve(root, path, m.group(1))))
    return files, edges


def include_problems(root, files, edges):
    """Rules 1, 2 and 5: one message per offending include."""
    problems = []
    known = {f: layer_of(root, f) for f in files}
    for path, layer in known.items():
        if layer not in RANK:
            problems.append(f"{os.path.relpath(path, root)}: file outside the known layers ({', '.join(sorted(RANK))})")
    for path, lineno, name, target in edges:
        src_layer = known[path]
        if src_layer not in RANK:
            continue
        where = f'{os.path.relpath(path, root)}:{lineno}: #include "{name}"'
        if target is None:
            problems.append(f"{where}: resolves to no file of src/, field_solver/, studies/ or the file's folder")
            continue
        dst_layer = GENERATED[name] if target == "generated" else layer_of(root, target)
        if dst_layer not in RANK:
            problems.append(f"{where}: includes a file outside the known layers")
        elif RANK[dst_layer] > RANK[src_layer]:
            problems.append(f"{where}: {src_layer} (layer {RANK[src_layer]}) includes "
                            f"{dst_layer} (layer {RANK[dst_layer]}): includes must point down")
        elif src_layer == dst_layer == "field_solver":
            a, b = fem_part(root, path), fem_part(root, target)
            if a not in FEM_PARTS or b not in FEM_PARTS:
                problems.append(f"{where}: field_solver/ files live in its parts ({', '.join(FEM_PARTS)})")
            elif FEM_PARTS[b] > FEM_PARTS[a]:
                problems.append(f"{where}: field_solver/{a} includes field_solver/{b}: the FEM's parts are "
                                "layered mesh < fe < solve < field_io")
        elif dst_layer == "studies":
            src_client, dst_client = client_of(root, path), client_of(root, target)
            if src_client != dst_client:
                problems.append(f"{where}: {src_client} includes {dst_client}: a study is one room "
                                "(shared code goes down into src/analysis/ or src/report/)")
    return problems


def unit_graph(root, edges):
    """Unit -> set of units it includes (resolved, generated header left out)."""
    graph = {}
    for path, _, _, target in edges:
        if target in (None, "generated"):
            continue
        a, b = unit_of(root, path), unit_of(root, target)
        if a != b:
            graph.setdefault(a, set()).add(b)
    return graph


def cycles(graph):
    """Every strongly connected component of more than one unit (Tarjan), each as a sorted list."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        work = [(v, iter(sorted(graph.get(v, ()))))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        while work:
            node, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                    advanced = True
                    break
                if w in on_stack:
                    low[node] = min(low[node], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.append(w)
                    if w == node:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def shared_layer_problems(root, files, graph):
    """Rule 3: units of src/analysis/ and src/report/ reached by fewer than two clients."""
    clients = {}
    for f in files:
        c = client_of(root, f)
        if c:
            clients.setdefault(c, set()).add(unit_of(root, f))
    reached_by = {}
    for client, units in clients.items():
        seen, todo = set(), list(units)
        while todo:
            u = todo.pop()
            if u in seen:
                continue
            seen.add(u)
            todo.extend(graph.get(u, ()))
        for u in seen:
            reached_by.setdefault(u, set()).add(client)
    problems = []
    shared = {}
    for f in sorted(files):
        if layer_of(root, f) in SHARED:
            shared.setdefault(unit_of(root, f), []).append(os.path.relpath(f, root))
    for u, paths in sorted(shared.items()):
        users = sorted(reached_by.get(u, ()))
        if len(users) < 2:
            who = users[0] if users else "no client"
            shown = next((p for p in paths if p.endswith(".hpp")), paths[0])
            problems.append(f"{shown}: in the shared layer but used by {who} alone: a single study's engine or report "
                            "lives in its study folder (studies/<name>/)")
    return problems


def check(root):
    """List of problem messages for the tree at root."""
    files, edges = scan(root)
    problems = include_problems(root, files, edges)
    graph = unit_graph(root, edges)
    for comp in cycles(graph):
        problems.append(f"{comp[-1]}: include cycle through the units {', '.join(comp)}")
    problems += shared_layer_problems(root, files, graph)
    return problems


def stats(root):
    """Files and lines per layer, the largest study folder, includes up and cycles (ARCHITECTURE.md's numbers)."""
    files, edges = scan(root)
    per = {}
    for f in files:
        rel = os.path.relpath(f, root).split(os.sep)
        key = "/".join(rel[:2]) if rel[0] in ("src", "field_solver") and len(rel) > 2 else rel[0]
        with open(f, encoding="utf-8", errors="replace") as fh:
            n = sum(1 for _ in fh)
        c = per.setdefault(key, [0, 0])
        c[0] += 1
        c[1] += n
    for key in sorted(per):
        print(f"{key}: {per[key][0]} files, {per[key][1]} lines")
    studies = {}
    for f in files:
        c = client_of(root, f)
        if c and c.startswith("studies/"):
            studies.setdefault(c, []).append(f)
    if studies:
        big = max(studies, key=lambda s: len(studies[s]))
        print(f"largest study: {big}, {len(studies[big])} files in 1 folder")
    problems = include_problems(root, files, edges)
    up = sum(1 for p in problems if "must point down" in p)
    print(f"includes up: {up}; cycles: {len(cycles(unit_graph(root, edges)))}")
    return 0


def self_test():
    """The checker must pass a clean tree and name each kind of violation."""
    clean = {
        "src/core/errors.hpp": "#pragma once\n",
        "src/core/config.hpp": '#include "core/errors.hpp"\n',
        "src/fields/magnet.hpp": '#include "core/config.hpp"\n',
        "src/probe/mounting.hpp": '#include "fields/magnet.hpp"\n',
        "src/io/tables.hpp": '#include "probe/mounting.hpp"\n#include <vector>\n',
        "field_solver/mesh/mesh.hpp": '#include "io/tables.hpp"\n',
        "field_solver/mesh/mesh.cpp": '#include "mesh.hpp"\n',
        "field_solver/fe/element.hpp": '#include "field_solver/mesh/mesh.hpp"\n',
        "src/analysis/sweep.hpp": '#include "io/tables.hpp"\n#include "field_solver/mesh/mesh.hpp"\n',
        "src/analysis/sweep.cpp": '#include "analysis/sweep.hpp"\n',
        "src/report/study_output.hpp": '#include "analysis/sweep.hpp"\n#include "magenc_version.hpp"\n',
        "src/analysis/extra.hpp": '#include "core/errors.hpp"\n',
        "studies/s/s.cpp": '#include "report/study_output.hpp"\n#include "s_engine.hpp"\n#include "analysis/extra.hpp"\n',
        "studies/s/s_engine.hpp": '#include "analysis/sweep.hpp"\n',
        "studies/t/t.cpp": '#include "report/study_output.hpp"\n',
        "apps/a.cpp": '#include "report/study_output.hpp"\n#include "analysis/extra.hpp"\n',
    }
    violating = {
        "analysis includes report": ("src/analysis/extra.hpp", '#include "report/study_output.hpp"\n',
                                     "analysis (layer 5) includes report (layer 6)"),
        "field_solver includes analysis": ("field_solver/solve/bad.cpp", '  #  include "analysis/sweep.hpp"\n',
                                           "field_solver (layer 4) includes analysis (layer 5)"),
        "core includes fields": ("src/core/bad.hpp", '#include "fields/magnet.hpp"\n',
                                 "core (layer 0) includes fields (layer 1)"),
        "fields includes probe": ("src/fields/bad.cpp", '#include "probe/mounting.hpp"\n',
                                  "fields (layer 1) includes probe (layer 2)"),
        "io includes field_solver": ("src/io/bad.cpp", '#include "field_solver/mesh/mesh.hpp"\n',
                                     "io (layer 3) includes field_solver (layer 4)"),
        "analysis includes a study": ("src/analysis/extra.hpp", '#include "studies/s/s_engine.hpp"\n',
                                      "analysis (layer 5) includes studies (layer 7)"),
        "FEM parts upward": ("field_solver/mesh/bad.cpp", '#include "field_solver/fe/element.hpp"\n',
                             "field_solver/mesh includes field_solver/fe"),
        "a study includes another": ("studies/t/t_engine.cpp", '#include "studies/s/s_engine.hpp"\n',
                                     "studies/t includes studies/s: a study is one room"),
        "a tool includes a study": ("apps/b.cpp", '#include "studies/s/s_engine.hpp"\n',
                                    "apps/b includes studies/s"),
        "unknown header": ("src/io/bad.cpp", '#include "io/missing.hpp"\n', "resolves to no file"),
        "single-study engine in analysis": ("src/analysis/only_s.hpp", '#include "core/errors.hpp"\n',
                                            "used by no client alone"),
        "include cycle": ("src/core/errors.hpp", '#include "core/config.hpp"\n', "include cycle"),
    }

    def clean_failure(root):
        problems = check(root)
        return "the clean tree is reported:\n  " + "\n  ".join(problems) if problems else None

    code = run_self_test(check, clean, violating, clean_failure, at=lambda rel: rel.rsplit(".", 1)[0])
    # One more planted tree: an analysis unit reached by one study only must be named with that study.
    import tempfile
    from checker_selftest import write
    with tempfile.TemporaryDirectory() as tmp:
        for rel, text in clean.items():
            write(tmp, rel, text)
        write(tmp, "src/analysis/only_s.hpp", '#include "core/errors.hpp"\n')
        write(tmp, "studies/s/s_engine.hpp", '#include "analysis/sweep.hpp"\n#include "analysis/only_s.hpp"\n')
        problems = check(tmp)
        expected = "src/analysis/only_s.hpp: in the shared layer but used by studies/s alone"
        if len(problems) != 1 or not problems[0].startswith(expected):
            print(f"self-test FAILED: engine used by one study: expected '{expected}', got {problems}")
            code = 1
        else:
            print(f"self-test ok: engine used by one study: {problems[0]}")
    return code


def main(argv):
    if len(argv) > 1 and argv[1] == "--self-test":
        return self_test()
    if len(argv) > 1 and argv[1] == "--stats":
        return stats(repo_root(argv[1:], __file__))
    root = repo_root(argv, __file__)
    problems = check(root)
    for p in problems:
        print(p)
    n = sum(1 for top in SCANNED for _, _, fs in os.walk(os.path.join(root, top)) for f in fs if f.endswith(SOURCE_EXT))
    if problems:
        print(f"check_includes: {len(problems)} problem(s) ({n} files checked)")
        return 1
    print(f"check_includes: {n} files, every include points down, no cycle, no single-client unit in the shared layer")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
