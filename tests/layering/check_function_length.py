#!/usr/bin/env python3
"""No function over 100 lines outside the numerical kernels ARCHITECTURE.md lists.

    check_function_length.py ROOT        scan ROOT's src/, field_solver/, apps/, studies/, python/
    check_function_length.py --self-test planted functions of 100 and 101 lines, scopes, lambdas

A function's length is counted from the first line of its signature to its closing brace. The scan
strips comments and string literals, then follows braces: a brace after a namespace, class, struct,
enum or union head opens a scope; a brace after a parenthesized head in a scope opens a function
(its nested braces belong to it). The exceptions are the rows "| lines | `name` (`file`) | why |"
of the table under "No function outside a numerical kernel" in ARCHITECTURE.md; a listed function
that is no longer over the limit is reported too (the list must stay true).
Exit 0 when every long function is listed and every listed one is long, 1 otherwise.
"""
import os
import re
import sys
import tempfile

LIMIT = 100
DIRS = ("src", "field_solver", "apps", "studies", "python")
SCOPE_HEAD = re.compile(r"\b(namespace|class|struct|enum|union)\b|extern\s+\"C\"")


def strip_code(text):
    """Comments and the insides of string and character literals become blanks (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            end = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + re.sub(r"[^\n]", " ", text[i + 2:end - 2]) if end - i >= 4 else text[i:end])
            i = end
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # digit separator 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * (min(j, n) - i - 1) + (c if j < n else ""))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, last line) of every function body at namespace or class scope."""
    code = strip_code(text)
    found, stack, head_start = [], [], 0
    line_of = [0] * (len(code) + 1)
    line = 1
    for k, ch in enumerate(code):
        line_of[k] = line
        if ch == "\n":
            line += 1
    in_function = 0
    for k, ch in enumerate(code):
        if ch == "{":
            head = code[head_start:k]
            kind = "block"
            if in_function == 0:
                h = head.strip()
                if SCOPE_HEAD.search(h) and "(" not in h.split("{")[0]:
                    kind = "scope"
                elif re.search(r"\)\s*(const|noexcept|override|final|mutable|->\s*[\w:<>,\s*&]+|\s)*$", h) and \
                        not re.search(r"=\s*\[", h) and not h.startswith(("if", "for", "while", "switch")):
                    kind = "function"
            if kind == "function":
                h = code[head_start:k]
                first = head_start + (len(h) - len(h.lstrip()))
                m = re.search(r"([~\w:]+|operator\s*\S+)\s*\(", h)
                name = m.group(1).split("::")[-1] if m else "?"
                stack.append(("function", name, line_of[first]))
                in_function += 1
            else:
                stack.append((kind, None, None))
            head_start = k + 1
        elif ch == "}":
            if stack:
                kind, name, first = stack.pop()
                if kind == "function":
                    in_function -= 1
                    found.append((name, first, line_of[k]))
            head_start = k + 1
        elif ch == ";" or (ch == ":" and in_function == 0 and re.search(r"\b(public|private|protected)\s*$",
                                                                          code[head_start:k])):
            head_start = k + 1
        elif ch == "#" and code[head_start:k].strip() == "":  # preprocessor line
            j = code.find("\n", k)
            while j > 0 and code[j - 1] == "\\":
                j = code.find("\n", j + 1)
            head_start = (len(code) if j < 0 else j) + 1
    return found


def long_functions(root):
    out = []
    for d in DIRS:
        for dirpath, _, files in os.walk(os.path.join(root, d)):
            for f in sorted(files):
                if f.endswith((".cpp", ".hpp", ".h", ".cc")):
                    path = os.path.join(dirpath, f)
                    with open(path, encoding="utf-8", errors="replace") as fh:
                        for name, a, b in functions(fh.read()):
                            if b - a + 1 > LIMIT:
                                out.append((b - a + 1, name, os.path.relpath(path, root)))
    return out


def listed_exceptions(root):
    """{(name, file)} from ARCHITECTURE.md's table of long kernels."""
    path = os.path.join(root, "ARCHITECTURE.md")
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    i = text.find("No function outside a numerical kernel")
    if i < 0:
        return None
    rows = set()
    for line in text[i:].splitlines()[1:]:
        if line.startswith("#"):
            break
        m = re.match(r"\|\s*\d+\s*\|\s*`([^`]+)`\s*\(`([^`]+)`\)", line)
        if m:
            rows.add((m.group(1), m.group(2)))
    return rows


def check(root):
    listed = listed_exceptions(root)
    if listed is None:
        print("check_function_length: ARCHITECTURE.md has no section 'No function outside a numerical kernel'")
        return 1
    long = long_functions(root)
    bad = 0
    for n, name, path in sorted(long, reverse=True):
        if (name, path) not in listed:
            print(f"{path}: {name} is {n} lines (limit {LIMIT}): split it along its steps, or list it in "
                  "ARCHITECTURE.md with the reason it is a kernel")
            bad += 1
    present = {(name, path) for _, name, path in long}
    for name, path in sorted(listed - present):
        print(f"ARCHITECTURE.md lists {name} ({path}) as over {LIMIT} lines: it is not (any more): update the table")
        bad += 1
    print(f"check_function_length: {len(long)} functions over {LIMIT} lines, {len(listed)} listed, {bad} problems")
    return 1 if bad else 0


def self_test():
    def body(lines):
        return "\n".join(["  x += 1;"] * lines)
    planted = {
        # (file text, expected long function names)
        "a.cpp": ("namespace n {\nnamespace {\nint ok() {\n" + body(98) + "\n}\n}  // namespace\n"
                  "int too_long(int a,\n             int b) {\n" + body(98) + "\n}\n}  // namespace n\n", {"too_long"}),
        "b.hpp": ("struct S {\n public:\n  void m() const {\n" + body(99) + "\n  }\n  int k = 0;\n};\n"
                  "class C {\n  void fine() {\n    auto f = [&]() {\n" + body(40) + "\n    };\n  }\n};\n", {"m"}),
        "c.cpp": ("// a comment with { braces\nconst char* s = \"{ not a scope\";\n"
                  "int f() {\n  if (a) {\n" + body(50) + "\n  }\n  for (;;) {\n" + body(50) + "\n  }\n}\n", {"f"}),
        "d.cpp": ("#define X(a) { a }\nstatic const auto table = [] {\n" + body(120) + "\n}();\n"
                  "int g() { return 1; }\n", set()),
    }
    bad = 0
    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "src"))
        for f, (text, expect) in planted.items():
            with open(os.path.join(d, "src", f), "w") as fh:
                fh.write(text)
        got = {}
        for n, name, path in long_functions(d):
            got.setdefault(os.path.basename(path), set()).add(name)
        for f, (_, expect) in planted.items():
            if got.get(f, set()) != expect:
                print(f"self-test: {f}: found {sorted(got.get(f, set()))}, expected {sorted(expect)}")
                bad += 1
        # The listing rules: an unlisted long function and a stale row both fail.
        with open(os.path.join(d, "ARCHITECTURE.md"), "w") as fh:
            fh.write("No function outside a numerical kernel is longer than 100 lines.\n\n"
                     "| lines | function | why |\n| --- | --- | --- |\n"
                     "| 101 | `too_long` (`src/a.cpp`) | kernel |\n| 120 | `gone` (`src/z.cpp`) | kernel |\n")
        if check(d) == 0:
            print("self-test: an unlisted long function (m, f) and a stale row (gone) passed")
            bad += 1
    print(f"check_function_length self-test: {'ok' if bad == 0 else str(bad) + ' failures'}")
    return 1 if bad else 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(check(sys.argv[1]))
