#!/usr/bin/env python3
"""Numeric comparison of two text outputs of a study (CSV, plot data, summary.md).

    scripts/compare_numbers.py FILE_A FILE_B [--rel REL] [--abs ABS]
    scripts/compare_numbers.py --self-test

The two files must have the same lines with the same words; only numbers may differ, and
each by at most ABS (default 1e-12: round-off of values that are zero, in deg, mm or T) or
  - tables (.csv, .dat, .txt): REL x the largest |value| of its column in FILE_A (a column is a
    comma- or blank-separated field of a line; a column of values ~1e-13 around 10 deg ones
    is compared at the 10 deg scale, which is what "the same result" means for a spectrum), or
    one unit in the last digit when both are printed alike (0.00137415 vs 0.00137416);
  - other text (summary.md): REL x |value| or one unit in the last digit printed, the larger
    (a printed 0.4721 may become 0.4722 when the unprinted digits move across a rounding edge;
    the unit is allowed only between numbers printed with as many significant digits).
Outputs that grew are still comparable: a CSV with a header row is compared column by column by
name (columns only in FILE_B are listed as added; a column missing from FILE_B is a difference),
and a config.toml key by key (keys only in FILE_B, new settings at their defaults, are listed as
added; a key missing or with another value is a difference).
Exit 0 when every number is within its tolerance, 1 otherwise (the worst differences are
printed), 2 on bad arguments. scripts/compare_outputs.sh diff --tol REL calls it for every file
whose bytes differ.
"""
import argparse
import math
import re
import sys

NUM = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|inf)\b", re.IGNORECASE)
TABLE_SUFFIXES = (".csv", ".dat", ".txt")


def split_numbers(line):
    """(words, numbers): the line's text with every number replaced by '#', and the numbers' texts."""
    nums = [m.group(0) for m in NUM.finditer(line)]
    return NUM.sub("#", line), nums


def significant_digits(text):
    mant = text.lower().partition("e")[0].lstrip("+-").replace(".", "").lstrip("0")
    return len(mant)


def rounding_unit(x, y):
    """One unit in the last digit when x and y are printed alike (the same number of significant
    digits: a rounding edge moved), else 0 (the scale rule alone)."""
    if "e" in (x + y).lower() or significant_digits(x) != significant_digits(y):
        return 0.0
    return min(last_digit_unit(x), last_digit_unit(y))


def last_digit_unit(text):
    """One unit in the last digit of a printed number: 0.4721 -> 1e-4, 3.2e-05 -> 1e-6, 12 -> 1."""
    mant, _, exp = text.lower().partition("e")
    mant = mant.lstrip("+-")
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    return 10.0 ** (-decimals + (int(exp) if exp else 0))


def columns(line):
    return [c for c in re.split(r"[,\s]+", line.strip()) if c != ""]


def same_value(a, b):
    return (math.isnan(a) and math.isnan(b)) or a == b


def toml_keys(lines):
    """{"section.key": value text} of a flat TOML file (comments and blank lines left out)."""
    out, section = {}, ""
    for line in lines:
        t = line.split("#", 1)[0].strip() if not line.strip().startswith(("\"", "'")) else line.strip()
        if not t:
            continue
        if t.startswith("[") and t.endswith("]"):
            section = t.strip("[]").strip()
            continue
        key, eq, value = t.partition("=")
        if eq:
            out[(section + "." if section else "") + key.strip()] = value.strip()
    return out


def compare_toml(lines_a, lines_b, notes):
    a, b = toml_keys(lines_a), toml_keys(lines_b)
    problems = [f"key {k} = {v} missing" for k, v in a.items() if k not in b]
    problems += [f"key {k}: {v} vs {b[k]}" for k, v in a.items() if k in b and b[k] != v]
    added = [k for k in b if k not in a]
    if added:
        notes.append(f"{len(added)} added keys ({', '.join(added[:6])}{', ...' if len(added) > 6 else ''})")
    return problems


def is_header(line):
    cells = [c.strip() for c in line.split(",")]
    return len(cells) > 1 and not any(NUM.fullmatch(c) for c in cells)


def compare_csv_by_name(lines_a, lines_b, rel, abs_tol, notes):
    """CSV files whose header rows differ: the columns of FILE_A, found by name in FILE_B."""
    ha, hb = lines_a[0].split(","), lines_b[0].split(",")
    missing = [c for c in ha if c not in hb]
    if missing:
        return [f"columns missing: {', '.join(missing)}"], 0.0
    added = [c for c in hb if c not in ha]
    notes.append(f"{len(added)} added columns ({', '.join(added[:6])}{', ...' if len(added) > 6 else ''})")
    idx = [hb.index(c) for c in ha]
    proj = [",".join(line.split(",")[i] if i < len(line.split(",")) else "" for i in idx) for line in lines_b]
    return compare_lines(lines_a, [lines_a[0]] + proj[1:], True, rel, abs_tol)


def compare(path_a, path_b, rel, abs_tol=1e-12, notes=None):
    notes = [] if notes is None else notes
    with open(path_a, encoding="utf-8", errors="replace") as f:
        lines_a = f.read().splitlines()
    with open(path_b, encoding="utf-8", errors="replace") as f:
        lines_b = f.read().splitlines()
    if path_a.endswith(".toml"):
        return compare_toml(lines_a, lines_b, notes), 0.0
    if (path_a.endswith(".csv") and lines_a and lines_b and lines_a[0] != lines_b[0] and is_header(lines_a[0])
            and is_header(lines_b[0])):
        if len(lines_a) != len(lines_b):
            return [f"line count {len(lines_a)} vs {len(lines_b)}"], 0.0
        return compare_csv_by_name(lines_a, lines_b, rel, abs_tol, notes)
    return compare_lines(lines_a, lines_b, path_a.endswith(TABLE_SUFFIXES), rel, abs_tol)


def compare_lines(lines_a, lines_b, table, rel, abs_tol):
    problems = []
    if len(lines_a) != len(lines_b):
        return [f"line count {len(lines_a)} vs {len(lines_b)}"], 0.0
    scale = {}
    if table:  # column scales from FILE_A
        for la in lines_a:
            for i, c in enumerate(columns(la)):
                try:
                    v = abs(float(c))
                except ValueError:
                    continue
                if math.isfinite(v):
                    scale[i] = max(scale.get(i, 0.0), v)
    worst = 0.0  # worst |a - b| / tolerance
    for n, (la, lb) in enumerate(zip(lines_a, lines_b), 1):
        if la == lb:
            continue
        if table:
            ca, cb = columns(la), columns(lb)
            if len(ca) != len(cb):
                problems.append(f"line {n}: {len(ca)} vs {len(cb)} fields")
                continue
            pairs = [(i, x, y) for i, (x, y) in enumerate(zip(ca, cb)) if x != y]
            for i, x, y in pairs:
                try:
                    a, b = float(x), float(y)
                except ValueError:
                    problems.append(f"line {n} field {i + 1}: '{x}' vs '{y}'")
                    continue
                if same_value(a, b):
                    continue
                tol = max(rel * scale.get(i, 0.0), abs_tol, rounding_unit(x, y))
                d = abs(a - b)
                if not (d <= tol):
                    problems.append(f"line {n} field {i + 1}: {x} vs {y} (|diff| {d:.3g} > {tol:.3g})")
                worst = max(worst, d / tol if tol > 0 else math.inf)
        else:
            wa, na = split_numbers(la)
            wb, nb = split_numbers(lb)
            if wa != wb or len(na) != len(nb):
                problems.append(f"line {n}: text differs:\n  < {la}\n  > {lb}")
                continue
            for x, y in zip(na, nb):
                if x == y:
                    continue
                a, b = float(x), float(y)
                if same_value(a, b):
                    continue
                tol = max(rel * abs(a), rounding_unit(x, y), abs_tol)
                d = abs(a - b)
                if not (d <= tol * (1 + 1e-12)):
                    problems.append(f"line {n}: {x} vs {y} (|diff| {d:.3g} > {tol:.3g})")
                worst = max(worst, d / tol)
    return problems, worst


def self_test():
    """Planted cases: each must be judged as stated (a checker that passes everything fails here)."""
    import os
    import tempfile
    cases = [  # (name, suffix, text A, text B, must agree)
        ("equal bytes", ".csv", "a,b\n1,2\n", "a,b\n1,2\n", True),
        ("round-off at the column scale", ".csv", "x,y\n1e-13,10\n0,5\n", "x,y\n-4e-14,10\n0,5\n", True),
        ("a column of round-off", ".csv", "x\n1e-13\n", "x\n-4e-14\n", True),
        ("a small column that moved", ".csv", "x\n1e-8\n", "x\n2e-8\n", False),
        ("last digit of a 6-digit cell", ".csv", "x,y\n0.00137415,1\n", "x,y\n0.00137416,1\n", True),
        ("two digits of a 6-digit cell", ".csv", "x,y\n0.00137415,1\n", "x,y\n0.00137417,1\n", False),
        ("a real change", ".csv", "x,y\n1.0,10\n", "x,y\n1.001,10\n", False),
        ("text cell changed", ".csv", "k,y\nsx,1\n", "k,y\nsy,1\n", False),
        ("added column", ".csv", "x,y\n1,2\n", "x,p,y\n1,bz,2\n", True),
        ("missing column", ".csv", "x,y\n1,2\n", "x\n1\n", False),
        ("extra row", ".csv", "x\n1\n", "x\n1\n2\n", False),
        ("last printed digit", ".md", "pp 0.4721 deg\n", "pp 0.4722 deg\n", True),
        ("two digits off", ".md", "pp 0.4721 deg\n", "pp 0.4723 deg\n", False),
        ("words changed", ".md", "pp 0.4721 deg\n", "p99 0.4721 deg\n", False),
        ("nan on both sides", ".dat", "1 nan\n", "1 NaN\n", True),
        ("nan on one side", ".dat", "1 nan\n", "1 0.5\n", False),
        ("added key", ".toml", "[a]\nx = 1\n", "[a]\nx = 1\ny = 2\n", True),
        ("changed key", ".toml", "[a]\nx = 1\n", "[a]\nx = 2\n", False),
        ("missing key", ".toml", "[a]\nx = 1\ny = 2\n", "[a]\nx = 1\n", False),
    ]
    bad = 0
    with tempfile.TemporaryDirectory() as d:
        for name, suffix, ta, tb, agree in cases:
            fa, fb = os.path.join(d, "a" + suffix), os.path.join(d, "b" + suffix)
            with open(fa, "w") as f:
                f.write(ta)
            with open(fb, "w") as f:
                f.write(tb)
            problems, _ = compare(fa, fb, 1e-9)
            if (not problems) != agree:
                print(f"self-test: '{name}' judged {'equal' if not problems else 'different'}, expected "
                      f"{'equal' if agree else 'different'} {problems}")
                bad += 1
    print(f"compare_numbers self-test: {len(cases) - bad} of {len(cases)} planted cases judged right")
    return 1 if bad else 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("file_a")
    p.add_argument("file_b")
    p.add_argument("--rel", type=float, default=1e-9, help="relative tolerance (default 1e-9)")
    p.add_argument("--abs", type=float, default=1e-12, help="absolute tolerance (default 1e-12)")
    args = p.parse_args()
    for name, v in (("--rel", args.rel), ("--abs", args.abs)):
        if not (v >= 0 and math.isfinite(v)):
            print(f"compare_numbers.py: {name} = {v}: allowed a finite value >= 0", file=sys.stderr)
            return 2
    notes = []
    problems, worst = compare(args.file_a, args.file_b, args.rel, args.abs, notes)
    if problems:
        for line in problems[:10]:
            print("  " + line)
        if len(problems) > 10:
            print(f"  ... {len(problems) - 10} more")
        return 1
    print(f"  within tolerance (worst difference {worst:.2g} of its tolerance)" + "".join("; " + n for n in notes))
    return 0


if __name__ == "__main__":
    sys.exit(main())
