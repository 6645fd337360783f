#!/usr/bin/env python3
"""Docs resolve: every relative link of every Markdown file and every docs/ path cited anywhere in
the repository exists.

    * Markdown (*.md): inline links and images [text](target), ![alt](target), and reference
      definitions [label]: target. Targets with a scheme (https:, mailto:) are not checked; a
      relative target must name an existing file or folder (relative to the Markdown file); a
      #fragment into a Markdown file must name one of its headings (GitHub's anchors). Code
      blocks and `code spans` are skipped.
      A table's first row must be followed by its separator row (a blank line inside a table
      would leave the rest as raw pipes).
    * Every text file (sources, scripts, CMake, TOML, Markdown): each path written as docs/...
      (repository-relative) must exist. A path may stop at a folder (docs/studies/).

Skipped: build folders (build*), .git, generated output (output/*/), fuzz corpora and
regression inputs (tests/fuzz/corpus, tests/fuzz/regressions: hostile data, not prose).

    check_links.py [ROOT]        ROOT: the repository (default: two levels up)
    check_links.py --self-test   plants broken links in temporary trees; each must be reported

Exit 0 when everything resolves; 1 with one line per broken link or path otherwise.
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from checker_selftest import repo_root, run_self_test  # noqa: E402 (tests/checker_selftest.py)

SKIP_DIRS = {".git", os.path.join("tests", "fuzz", "corpus"), os.path.join("tests", "fuzz", "regressions")}
FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*(<[^>]*>|[^)\s]+)(?:\s+\"[^\"]*\")?\s*\)")
REF_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")
# A repository path starting with docs/ (not part of a longer path such as tests/docs/ or ../other/docs/).
DOCS_PATH = re.compile(r"(?<![\w./~-])" + "docs" + r"/[\w./-]*")
TABLE_SEPARATOR = re.compile(r"^\s*\|?\s*:?-+:?\s*(\|\s*:?-+:?\s*)*\|?\s*$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")


def skipped(rel_dir):
    if rel_dir == ".":
        return False
    parts = rel_dir.split(os.sep)
    if parts[0].startswith("build") or parts[0].startswith(".git"):
        return True
    if parts[0] == "output" and len(parts) > 1:
        return True
    return any(rel_dir == d or rel_dir.startswith(d + os.sep) for d in SKIP_DIRS)


def text_files(root):
    """(relative path, text) of every UTF-8 text file to check."""
    for dirpath, dirnames, files in os.walk(root):
        rel_dir = os.path.relpath(dirpath, root)
        if skipped(rel_dir):
            dirnames[:] = []
            continue
        dirnames.sort()
        for f in sorted(files):
            path = os.path.join(dirpath, f)
            if os.path.getsize(path) > 2_000_000:
                continue
            try:
                with open(path, encoding="utf-8") as fh:
                    text = fh.read()
            except (UnicodeDecodeError, OSError):
                continue
            if "\0" in text:
                continue
            yield os.path.relpath(path, root), text


def slug(heading):
    """GitHub's anchor of a heading text."""
    text = CODE_SPAN.sub(lambda m: m.group(2), heading)
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links: their text
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def prose_lines(text, keep_code_spans=False):
    """(line number, line) of Markdown text outside fenced code blocks; code spans removed unless kept."""
    fenced = False
    for lineno, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield lineno, line if keep_code_spans else CODE_SPAN.sub("", line)


def anchors(path, cache):
    if path not in cache:
        found = set()
        counts = {}
        try:
            with open(path, encoding="utf-8") as fh:
                text = fh.read()
        except (UnicodeDecodeError, OSError):
            text = ""
        for _, line in prose_lines(text, keep_code_spans=True):
            m = HEADING.match(line)
            if m:
                s = slug(m.group(2))
                n = counts.get(s, 0)
                counts[s] = n + 1
                found.add(s if n == 0 else f"{s}-{n}")
        # Explicit anchors (<a id="x"> / <a name="x">).
        found |= set(re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", text))
        cache[path] = found
    return cache[path]


def check_tables(rel, text):
    """A table's first row must be followed by its separator row: rows after a blank line inside a
    table render as raw pipes."""
    problems = []
    lines = list(prose_lines(text, keep_code_spans=True))
    for i, (lineno, line) in enumerate(lines):
        row = line.strip().startswith("|") and line.strip().endswith("|") and len(line.strip()) > 1
        starts = row and (i == 0 or not lines[i - 1][1].lstrip().startswith("|") or lines[i - 1][0] != lineno - 1)
        if starts and not (i + 1 < len(lines) and lines[i + 1][0] == lineno + 1
                           and TABLE_SEPARATOR.match(lines[i + 1][1])):
            problems.append(f"{rel}:{lineno}: table rows without a header and separator row "
                            "(a blank line inside a table?)")
    return problems


def check_markdown(root, rel, text, cache):
    problems = check_tables(rel, text)
    base = os.path.dirname(os.path.join(root, rel))
    for lineno, line in prose_lines(text):
        targets = [m.group(1) for m in INLINE_LINK.finditer(line)]
        m = REF_DEF.match(line)
        if m:
            targets.append(m.group(1))
        for target in targets:
            target = target.strip("<>")
            if not target or SCHEME.match(target):
                continue
            path_part, _, fragment = target.partition("#")
            where = f"{rel}:{lineno}: link '{target}'"
            if path_part:
                dest = os.path.normpath(os.path.join(base, path_part))
                if not os.path.exists(dest):
                    problems.append(f"{where} resolves to no file ({os.path.relpath(dest, root)})")
                    continue
            else:
                dest = os.path.join(root, rel)
            if fragment and dest.endswith(".md") and os.path.isfile(dest):
                if fragment not in anchors(dest, cache):
                    problems.append(f"{where}: {os.path.relpath(dest, root)} has no heading with the anchor #{fragment}")
    return problems


def check_cited_paths(root, rel, text):
    problems = []
    for lineno, line in enumerate(text.splitlines(), 1):
        for cited in sorted({m.group(0).rstrip(".") for m in DOCS_PATH.finditer(line)}):
            if not os.path.exists(os.path.join(root, cited)):
                problems.append(f"{rel}:{lineno}: cited path {cited} does not exist")
    return problems


def check(root):
    """Problem lines for the tree at root."""
    problems = []
    cache = {}
    for rel, text in text_files(root):
        if rel.endswith(".md"):
            problems += check_markdown(root, rel, text, cache)
        problems += check_cited_paths(root, rel, text)
    return problems


def self_test():
    """Clean tree passes; each planted broken link or path is reported, once, at its file."""
    d = "do" + "cs"  # keeps this file's own text free of cited paths that do not exist
    clean = {
        "README.md": (f"# Title\n\nSee [physics]({d}/physics.md#the-magnet), ![pic](fig/a.png), "
                      f"[web](https://example.org/x.md), [top](#title), [dir]({d}/studies/).\n"
                      f"```\n[not a link](nowhere.md)\n```\nand `[code](nowhere.md)` too.\n"
                      f"[ref]: {d}/physics.md\n"),
        f"{d}/physics.md": ("# Physics\n\n## The magnet\n\n| a | b |\n|---|:--:|\n| `x|y` | 1 |\n\n"
                            "## Linear solvers (`fem.solver`)\n\n[back](../README.md)\n"),
        f"{d}/studies/radius.md": f"# Radius\n\n[solvers](../physics.md#linear-solvers-femsolver)\n",
        "fig/a.png": "png\n",
        "src/core/x.cpp": f"// conventions: {d}/physics.md, pages {d}/studies/<name>.md, ../other/{d}/gone.md\n",
        "build/ignored.md": "[broken](nowhere.md)\n",
        "output/run/summary.md": "[broken](nowhere.md)\n",
    }
    violating = {
        "broken relative link": (f"{d}/validation.md", "# Validation\n\n[interfaces](interface.md)\n",
                                 "resolves to no file"),
        "broken image": (f"{d}/studies/airgap.md", "# Airgap\n\n![plot](../../studies/figures/gone.png)\n",
                         "resolves to no file"),
        "broken anchor": (f"{d}/fem.md", "# FEM\n\n[magnet](physics.md#the-magnets)\n", "no heading with the anchor"),
        "broken reference definition": ("tests/README.md", "# Tests\n\n[ref]: ../missing/README.md\n",
                                        "resolves to no file"),
        "table broken by a blank line": (f"{d}/benchmarks.md",
                                         "# Speed\n\n| a | b |\n| --- | --- |\n| 1 | 2 |\n\n| 3 | 4 |\n",
                                         "table rows without a header"),
        "code cites a missing page": ("src/probe/y.hpp", f"// see {d}/probes.md, \"Arrays\"\n",
                                      "cited path " + d + "/probes.md does not exist"),
        "script cites a missing page": ("scripts/s.sh", f"# reads {d}/physics.md, not {d}/key.md\n",
                                        "cited path " + d + "/key.md does not exist"),
    }

    def clean_failure(root):
        problems = check(root)
        return "the clean tree is reported:\n  " + "\n  ".join(problems) if problems else None

    return run_self_test(check, clean, violating, clean_failure, at=lambda rel: rel + ":")


def main(argv):
    if len(argv) > 1 and argv[1] == "--self-test":
        return self_test()
    root = repo_root(argv, __file__)
    problems = check(root)
    for p in problems:
        print(p)
    n_md = sum(1 for rel, _ in text_files(root) if rel.endswith(".md"))
    if problems:
        print(f"check_links: {len(problems)} broken link(s) or cited path(s) ({n_md} Markdown files checked)")
        return 1
    print(f"check_links: {n_md} Markdown files, every relative link and cited docs path resolves")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
