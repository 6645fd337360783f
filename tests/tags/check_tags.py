#!/usr/bin/env python3
"""Catch2 tags use a fixed vocabulary (tests/README.md, "Tags"): every TEST_CASE
under tests/ has

  - exactly one layer tag, and in a folder that mirrors a source folder
    (tests/core, tests/fields, ..., tests/field_solver) it is that folder's;
  - otherwise only kind tags from KINDS below (none is required);
  - no tag twice, nothing between the brackets but tags;
  - a name without ';' (CMake splits lists on ';': catch_discover_tests would register
    two filters that match nothing; ',' is escaped by CatchAddTests.cmake) and without '[' or ']'
    (an unbalanced bracket makes CMake's list parsing join the following test names into one
    ctest entry whose filter matches nothing).

tests/README.md lists the same vocabulary (rows "| `[tag]` | ..." of its tag
tables): a tag added here but not there, or there but not here, is reported.

    check_tags.py [ROOT]        ROOT: the repository (default: two levels up)
    check_tags.py --self-test   runs the checker on synthetic trees in a temp
                                dir: a clean one must pass, violating ones fail

Exit 0 when clean; 1 with one line per problem otherwise.
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from checker_selftest import repo_root, run_self_test  # noqa: E402 (tests/checker_selftest.py)

LAYERS = ["core", "fields", "probe", "io", "analysis", "report", "field_solver", "apps", "studies"]
KINDS = ["physics", "closed-form", "convergence", "cross-check", "contract", "bad-input", "regression",
         "determinism", "faults", "cli", "mpi", "slow"]
SOURCE_EXT = (".cpp", ".hpp")
README_TAG_ROW = re.compile(r"^\|\s*`\[([^\]`]+)\]`\s*\|")


def strip_comments(text):
    """(text with // and /* */ comments blanked to spaces, same length and lines; [(start, end)] of the
    string and character literals in it)."""
    out, literals = [], []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == '"' or c == "'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            literals.append((i, j + 1))
            out.append(text[i:j + 1])
            i = j + 1
        elif text.startswith("//", i) or text.startswith("/*", i):
            j = (text.find("\n", i) if text[i + 1] == "/" else text.find("*/", i + 2))
            j = n if j < 0 else (j if text[i + 1] == "/" else j + 2)
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out), literals


STRING = r'"(?:[^"\\\n]|\\.)*"'
STRINGS = rf"((?:{STRING}\s*)+)"
TEST_CASE_CALL = re.compile(rf"\bTEST_CASE\s*\(\s*{STRINGS}(?:,\s*{STRINGS})?\)")
TEST_CASE_WORD = re.compile(r"\bTEST_CASE\b")


def literal(strings):
    """The value of adjacent C++ string literals (escapes \\" and \\\\ only)."""
    parts = re.findall(STRING, strings)
    return "".join(p[1:-1].replace('\\"', '"').replace("\\\\", "\\") for p in parts)


def test_cases(path):
    """[(line, name, tags or None)] of one file, plus [(line, problem)] for TEST_CASEs it cannot read."""
    with open(path, encoding="utf-8", errors="replace") as f:
        text, literals = strip_comments(f.read())
    cases, unreadable = [], []
    for m in TEST_CASE_WORD.finditer(text):
        if any(a <= m.start() < b for a, b in literals):
            continue
        line = text.count("\n", 0, m.start()) + 1
        if text[:m.start()].rstrip().endswith("#define"):
            continue
        call = TEST_CASE_CALL.match(text, m.start())
        if not call:
            unreadable.append((line, "TEST_CASE the checker cannot read (name and tags must be string literals)"))
            continue
        tags = literal(call.group(2)) if call.group(2) else None
        cases.append((line, literal(call.group(1)), tags))
    return cases, unreadable


def check_case(folder, name, tags):
    """Problems of one TEST_CASE (folder: first folder under tests/)."""
    problems = []
    if ";" in name:
        problems.append("name contains ';'")
    if "[" in name or "]" in name:
        problems.append("name contains '[' or ']'")
    if tags is None or not tags.strip():
        return problems + [f"no tags (needs one layer tag of {' '.join('[' + t + ']' for t in LAYERS)})"]
    found = re.findall(r"\[([^\[\]]*)\]", tags)
    rest = re.sub(r"\[[^\[\]]*\]", "", tags)
    if rest.strip():
        problems.append(f"text outside brackets in the tags: '{rest.strip()}'")
    unknown = [t for t in found if t not in LAYERS and t not in KINDS]
    if unknown:
        problems.append("tag(s) not in the vocabulary (tests/README.md): " + " ".join(f"[{t}]" for t in unknown))
    dup = sorted({t for t in found if found.count(t) > 1})
    if dup:
        problems.append("tag(s) given twice: " + " ".join(f"[{t}]" for t in dup))
    layers = [t for t in found if t in LAYERS]
    if len(layers) != 1:
        problems.append(f"{len(layers)} layer tags ({' '.join('[' + t + ']' for t in layers) or 'none'}), "
                        "needs exactly one")
    elif folder in LAYERS and layers[0] != folder:
        problems.append(f"layer tag [{layers[0]}] in tests/{folder}/ (tests/{folder}/ holds [{folder}] tests)")
    return problems


def readme_vocabulary(root):
    path = os.path.join(root, "tests", "README.md")
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as f:
        return {m.group(1) for line in f for m in [README_TAG_ROW.match(line)] if m}


def check(root):
    """All problems under root/tests, one line each."""
    problems = []
    tests = os.path.join(root, "tests")
    count = 0
    for dirpath, dirnames, filenames in os.walk(tests):
        dirnames.sort()
        for fn in sorted(filenames):
            if not fn.endswith(SOURCE_EXT):
                continue
            path = os.path.join(dirpath, fn)
            rel = os.path.relpath(path, root)
            parts = os.path.relpath(path, tests).split(os.sep)
            folder = parts[0] if len(parts) > 1 else ""
            cases, unreadable = test_cases(path)
            problems += [f"{rel}:{line}: {what}" for line, what in unreadable]
            for line, name, tags in cases:
                count += 1
                problems += [f'{rel}:{line}: "{name}": {p}' for p in check_case(folder, name, tags)]
    documented = readme_vocabulary(root)
    vocabulary = set(LAYERS) | set(KINDS)
    if documented is None:
        problems.append("tests/README.md: missing (it documents the tag vocabulary)")
    else:
        for t in sorted(vocabulary - documented):
            problems.append(f"tests/README.md: tag [{t}] of the checker is not documented (a row | `[{t}]` | ...)")
        for t in sorted(documented - vocabulary):
            problems.append(f"tests/README.md: documents tag [{t}] that the checker does not know")
    return problems, count


def self_test():
    readme = "# tests\n\n| tag | meaning |\n| --- | --- |\n" + "".join(
        f"| `[{t}]` | x |\n" for t in LAYERS + KINDS)
    clean = {
        "tests/README.md": readme,
        "tests/core/test_a.cpp": ('TEST_CASE("a one", "[core]") {}\n'
                                  'TEST_CASE("a two: multi-line"\n          " name",\n'
                                  '          "[core][physics]"  "[slow]") {}\n'
                                  '// TEST_CASE("commented out, never checked", "[nonsense]")\n'
                                  '/* TEST_CASE("block comment", "") */\n'
                                  'const char* s = "TEST_CASE in a string // not a comment";\n'),
        "tests/reliability/test_r.cpp": 'TEST_CASE("cross-cutting folder, any one layer", "[apps][cli]") {}\n',
        "tests/fields/util.hpp": "#define TEST_CASE_HELPER 1\n",
    }
    violating = {
        "unknown tag": ("tests/core/test_bad.cpp", 'TEST_CASE("x", "[core][fem]") {}\n', "not in the vocabulary"),
        "two layer tags": ("tests/core/test_bad.cpp", 'TEST_CASE("x", "[core][probe]") {}\n', "2 layer tags"),
        "no layer tag": ("tests/core/test_bad.cpp", 'TEST_CASE("x", "[physics]") {}\n', "0 layer tags"),
        "no tags": ("tests/core/test_bad.cpp", 'TEST_CASE("x") {}\n', "no tags"),
        "empty tags": ("tests/core/test_bad.cpp", 'TEST_CASE("x", "") {}\n', "no tags"),
        "layer of another folder": ("tests/io/test_bad.cpp", 'TEST_CASE("x", "[probe]") {}\n', "in tests/io/"),
        "tag twice": ("tests/core/test_bad.cpp", 'TEST_CASE("x", "[core][slow][slow]") {}\n', "given twice"),
        "text outside brackets": ("tests/core/test_bad.cpp", 'TEST_CASE("x", "[core] slow") {}\n', "outside brackets"),
        "semicolon in name": ("tests/core/test_bad.cpp", 'TEST_CASE("x; y", "[core]") {}\n', "contains ';'"),
        "bracket in name": ("tests/core/test_bad.cpp", 'TEST_CASE("x in (-90, 90]", "[core]") {}\n', "contains '[' or ']'"),
        "name not a literal": ("tests/core/test_bad.cpp", 'TEST_CASE(NAME, "[core]") {}\n', "cannot read"),
        "undocumented tag": ("tests/README.md", readme.replace("| `[slow]` | x |\n", ""), "[slow] of the checker"),
        "documented unknown tag": ("tests/README.md", readme + "| `[fem]` | x |\n", "documents tag [fem]"),
    }

    def clean_failure(root):
        problems, count = check(root)
        if problems or count != 3:
            return f"the clean tree gives {count} test cases (expected 3) and problems {problems}"
        return None

    return run_self_test(lambda root: check(root)[0], clean, violating, clean_failure, at=lambda rel: rel)


def main(argv):
    if len(argv) > 1 and argv[1] == "--self-test":
        return self_test()
    root = repo_root(argv, __file__)
    problems, count = check(root)
    for p in problems:
        print(p)
    if problems:
        print(f"check_tags: {len(problems)} problem(s) in {count} test cases")
        return 1
    if count == 0:
        print(f"check_tags: no TEST_CASE found under {root}/tests")
        return 1
    print(f"check_tags: {count} test cases, each with one layer tag and vocabulary tags only")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
