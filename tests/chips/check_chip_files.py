#!/usr/bin/env python3
"""Chip definitions (chips/*.toml, chips/README.md) keep to the configuration keys of docs/interfaces.md
"Sensor principles, environment, calibration (keys)" and name a source for every number.

Each chips/*.toml must
  - parse as TOML (Python's tomllib);
  - hold one table, [sensor], and in it only these keys:
        principle (required): "bz" | "inplane" | "xmr" | "amr"
        array: for bz "two" | "diff4" | "ring:N" (3 <= N <= 1024), for the others "point"
        r0_mm (bz only, > 0)
        field_min_mT, field_max_mT (>= 0; min < max when both are set)
        offset_cos_mT, offset_sin_mT (bz and inplane only), offset_cos_rel, offset_sin_rel (xmr and
        amr only), gain_mismatch, phase_error_deg, offset_cos_tc_uT_per_K, offset_sin_tc_uT_per_K
        direction: 1 | -1 | "auto"; zero_deg: a number | "auto"; gain_trim: "none" | "auto" (the chip's
        programmable direction, zero and side-shaft gain trim; each with a source like a number)
    (noise.* keys are declared only by the radius study, so a chip file holding one could not be
    loaded by every executable: they are refused here);
  - give every numeric key a source: a comment containing "source:" on the key's own line, or in the
    block of comment lines directly above it.

    check_chip_files.py [ROOT]        ROOT: the repository (default: two levels up)
    check_chip_files.py --self-test   runs the checker on synthetic trees in a temp dir: a clean one
                                      must pass, each violating one must give exactly one problem

Exit 0 when clean; 1 with one line per problem otherwise.
"""
import os
import re
import sys
import tomllib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from checker_selftest import repo_root, run_self_test  # noqa: E402 (tests/checker_selftest.py)

PRINCIPLES = ("bz", "inplane", "xmr", "amr")
NUMERIC_KEYS = {
    "r0_mm", "field_min_mT", "field_max_mT", "offset_cos_mT", "offset_sin_mT", "offset_cos_rel",
    "offset_sin_rel", "gain_mismatch", "phase_error_deg", "offset_cos_tc_uT_per_K",
    "offset_sin_tc_uT_per_K", "delay_us", "skew_us", "filter_hz", "sample_hz",
}
TIMING_KEYS = {"delay_us", "skew_us", "filter_hz", "sample_hz"}
STRING_KEYS = {"principle", "array"}
# The chip's settings (docs/interfaces.md "Rings, sensors off the axis"): allowed values, a source each.
SETTING_KEYS = {"direction": (1, -1, "1", "-1", "auto"), "zero_deg": ("auto",), "gain_trim": ("none", "auto")}
MT_OFFSETS = {"offset_cos_mT", "offset_sin_mT"}
REL_OFFSETS = {"offset_cos_rel", "offset_sin_rel"}
RING = re.compile(r"ring:([0-9]{1,5})$")
KEY_LINE = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=")
SOURCE = re.compile(r"#.*\bsource:\s*\S", re.IGNORECASE)


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def array_ok(principle, array):
    if principle != "bz":
        return array == "point"
    if array in ("two", "diff4"):
        return True
    m = RING.match(array)
    return bool(m) and 3 <= int(m.group(1)) <= 1024


def key_lines(lines):
    """{key: line number (1-based)} of the key assignments inside [sensor]."""
    out = {}
    table = None
    for n, line in enumerate(lines, 1):
        s = line.strip()
        if s.startswith("["):
            table = s
            continue
        m = KEY_LINE.match(line)
        if m and table == "[sensor]":
            out.setdefault(m.group(1), n)
    return out


def has_source(lines, n):
    """True when line n (1-based) carries a 'source:' comment, or the comment block right above it does."""
    if SOURCE.search(lines[n - 1]):
        return True
    i = n - 2
    while i >= 0 and lines[i].lstrip().startswith("#"):
        if SOURCE.search(lines[i]):
            return True
        i -= 1
    return False


def check_file(root, rel):
    path = os.path.join(root, rel)
    with open(path, "rb") as fh:
        raw = fh.read()
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        return [f"{rel}: does not parse as TOML: {e}"]
    problems = []
    for table in sorted(set(data) - {"sensor"}):
        problems.append(f"{rel}: [{table}]: a chip file holds only [sensor]"
                        + (" (noise.* keys are declared only by the radius study: not loadable by every "
                           "executable)" if table == "noise" else ""))
    sensor = data.get("sensor")
    if not isinstance(sensor, dict):
        return problems + [f"{rel}: no [sensor] table"]
    lines = raw.decode("utf-8").splitlines()
    where = key_lines(lines)

    def at(key):
        return f"{rel}:{where[key]}" if key in where else rel

    for key in sorted(set(SETTING_KEYS) & set(sensor)):
        v = sensor[key]
        ok = v in SETTING_KEYS[key] or (key == "zero_deg" and is_number(v) and abs(v) <= 360)
        if not ok:
            problems.append(f"{at(key)}: sensor.{key} = {v!r}: allowed {' | '.join(map(str, SETTING_KEYS[key]))}"
                            + (" or a number in [-360, 360]" if key == "zero_deg" else ""))
        elif key not in where or not has_source(lines, where[key]):
            problems.append(f"{at(key)}: sensor.{key} has no 'source:' comment on its line or directly above")
    for key in sorted(set(sensor) - NUMERIC_KEYS - STRING_KEYS - set(SETTING_KEYS)):
        problems.append(f"{at(key)}: sensor.{key} is not a chip-definition key "
                        f"(allowed: {', '.join(sorted(STRING_KEYS | NUMERIC_KEYS | set(SETTING_KEYS)))})")
    principle = sensor.get("principle")
    if principle is None:
        problems.append(f"{rel}: sensor.principle is missing (allowed: {' | '.join(PRINCIPLES)})")
    elif principle not in PRINCIPLES:
        problems.append(f"{at('principle')}: sensor.principle = {principle!r}: allowed {' | '.join(PRINCIPLES)}")
        principle = None
    if "array" in sensor:
        array = sensor["array"]
        if not isinstance(array, str) or (principle and not array_ok(principle, array)):
            allowed = "two | diff4 | ring:N (3 <= N <= 1024)" if principle == "bz" else "point"
            problems.append(f"{at('array')}: sensor.array = {array!r} with principle {principle!r}: allowed {allowed}")
    for key in sorted(NUMERIC_KEYS & set(sensor)):
        v = sensor[key]
        if not is_number(v):
            problems.append(f"{at(key)}: sensor.{key} = {v!r} is not a number")
            continue
        if key not in where or not has_source(lines, where[key]):
            problems.append(f"{at(key)}: sensor.{key} has no 'source:' comment on its line or directly above")
        if key == "r0_mm" and principle not in (None, "bz"):
            problems.append(f"{at(key)}: sensor.r0_mm does not apply to principle {principle!r} (bz arrays only)")
        if key == "r0_mm" and not v > 0:
            problems.append(f"{at(key)}: sensor.r0_mm = {v} must be > 0")
        if key in TIMING_KEYS and not v >= 0:
            problems.append(f"{at(key)}: sensor.{key} = {v} must be >= 0")
        if key in ("field_min_mT", "field_max_mT") and not v >= 0:
            problems.append(f"{at(key)}: sensor.{key} = {v} must be >= 0")
        if key in MT_OFFSETS and principle in ("xmr", "amr"):
            problems.append(f"{at(key)}: sensor.{key} (mT) does not apply to principle {principle!r} "
                            "(use offset_cos_rel / offset_sin_rel)")
        if key in REL_OFFSETS and principle in ("bz", "inplane"):
            problems.append(f"{at(key)}: sensor.{key} (relative) does not apply to principle {principle!r} "
                            "(use offset_cos_mT / offset_sin_mT)")
    lo, hi = sensor.get("field_min_mT"), sensor.get("field_max_mT")
    if is_number(lo) and is_number(hi) and not lo < hi:
        problems.append(f"{at('field_max_mT')}: field window min {lo} mT is not below max {hi} mT")
    return problems


def check(root):
    """List of problem lines for the chips/ folder of the tree at root."""
    base = os.path.join(root, "chips")
    if not os.path.isdir(base):
        return ["chips: folder missing"]
    files = sorted(f for f in os.listdir(base) if f.endswith(".toml"))
    if not files:
        return ["chips: no *.toml chip definitions"]
    problems = []
    for f in files:
        problems += check_file(root, os.path.join("chips", f))
    readme = os.path.join(base, "README.md")
    text = open(readme, encoding="utf-8").read() if os.path.isfile(readme) else None
    if text is None:
        problems.append("chips/README.md: missing (a table of the chip files)")
    else:
        problems += [f"chips/{f}: not listed in chips/README.md" for f in files if f not in text]
    return problems


def self_test():
    """The checker must pass a clean tree and name each kind of violation."""
    good_bz = ('[sensor]\nprinciple = "bz"\narray = "diff4"\n'
               'r0_mm = 1.1   # source: Some DS Rev 1, sec. 2\n'
               '# The window: a block of comments,\n# source: Some DS Rev 1, table 3\n'
               'field_min_mT = 35\nfield_max_mT = 70  # source: Some DS Rev 1, table 3\n'
               'delay_us = 96  # source: Some DS Rev 1, sec. 17\n')
    good_amr = ('[sensor]\nprinciple = "amr"\narray = "point"\n'
                'field_min_mT = 31.42  # source: Other DS Rev 6, sec. 2\n'
                'offset_cos_rel = 0.01 # source: Other DS Rev 6, table 9\n')
    readme = "| a.toml | b.toml |\n"
    clean = {"chips/a.toml": good_bz, "chips/b.toml": good_amr, "chips/README.md": readme}
    violating = {
        "not TOML": ("chips/a.toml", '[sensor]\nprinciple = "bz\n', "does not parse as TOML"),
        "unknown key": ("chips/a.toml", '[sensor]\nprinciple = "bz"\nsteps = 10 # source: x\n',
                        "sensor.steps is not a chip-definition key"),
        "other table": ("chips/a.toml", '[sensor]\nprinciple = "bz"\n[noise]\nadc_bits = 12\n',
                        "noise.* keys are declared only by the radius study"),
        "bad principle": ("chips/a.toml", '[sensor]\nprinciple = "hall"\n', "allowed bz | inplane | xmr | amr"),
        "missing principle": ("chips/a.toml", '[sensor]\narray = "two"\n', "sensor.principle is missing"),
        "point array on bz": ("chips/a.toml", '[sensor]\nprinciple = "bz"\narray = "point"\n',
                              "allowed two | diff4 | ring:N"),
        "ring too small": ("chips/a.toml", '[sensor]\nprinciple = "bz"\narray = "ring:2"\n',
                           "allowed two | diff4 | ring:N"),
        "ring array on xmr": ("chips/b.toml", '[sensor]\nprinciple = "xmr"\narray = "ring:8"\n',
                              "allowed point"),
        "r0 on inplane": ("chips/b.toml", '[sensor]\nprinciple = "inplane"\narray = "point"\n'
                          'r0_mm = 1.0 # source: x DS\n', "sensor.r0_mm does not apply"),
        "window min >= max": ("chips/a.toml", '[sensor]\nprinciple = "bz"\n'
                              'field_min_mT = 70 # source: x DS\nfield_max_mT = 35 # source: x DS\n',
                              "min 70 mT is not below max 35 mT"),
        "window equal": ("chips/a.toml", '[sensor]\nprinciple = "bz"\n'
                         'field_min_mT = 20 # source: x DS\nfield_max_mT = 20 # source: x DS\n',
                         "is not below max"),
        "window not a number": ("chips/a.toml", '[sensor]\nprinciple = "bz"\nfield_min_mT = "35" # source: x\n',
                                "is not a number"),
        "no source": ("chips/a.toml", '[sensor]\nprinciple = "bz"\nr0_mm = 1.1   # from the data sheet\n',
                      "sensor.r0_mm has no 'source:' comment"),
        "source not adjacent": ("chips/a.toml", '[sensor]\n# source: DS\nprinciple = "bz"\nr0_mm = 1.1\n',
                                "sensor.r0_mm has no 'source:' comment"),
        "empty source": ("chips/a.toml", '[sensor]\nprinciple = "bz"\nr0_mm = 1.1   # source:\n',
                         "sensor.r0_mm has no 'source:' comment"),
        "mT offset on amr": ("chips/b.toml", '[sensor]\nprinciple = "amr"\narray = "point"\n'
                             'offset_cos_mT = 0.1 # source: x DS\n', "(mT) does not apply to principle 'amr'"),
        "relative offset on bz": ("chips/a.toml", '[sensor]\nprinciple = "bz"\n'
                                  'offset_sin_rel = 0.1 # source: x DS\n', "(relative) does not apply"),
        "negative delay": ("chips/a.toml", '[sensor]\nprinciple = "bz"\ndelay_us = -96 # source: x DS\n',
                           "sensor.delay_us = -96 must be >= 0"),
        "timing without source": ("chips/a.toml", '[sensor]\nprinciple = "bz"\nsample_hz = 1000\n',
                                  "sensor.sample_hz has no 'source:' comment"),
        "negative r0": ("chips/a.toml", '[sensor]\nprinciple = "bz"\nr0_mm = -1 # source: x DS\n', "must be > 0"),
        "file missing from README": ("chips/c.toml", '[sensor]\nprinciple = "xmr"\n', "not listed in chips/README.md"),
    }

    def clean_failure(root):
        problems = check(root)
        return f"clean tree reported {problems}" if problems else None

    return run_self_test(check, clean, violating, clean_failure, at=lambda rel: rel)


def main(argv):
    if len(argv) > 1 and argv[1] == "--self-test":
        return self_test()
    problems = check(repo_root(argv, __file__))
    for p in problems:
        print(p)
    if not problems:
        print("chips: every chip definition uses the allowed keys and names its sources")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
