#!/usr/bin/env python3
"""One field's rows of two radius study outputs, against the study's own scales.

  scripts/compare_radius_fields.py BEFORE_DIR AFTER_DIR [--field fem] [--reference analytic]

For radius.csv, radius_spectra.csv and radius_budget.csv: the largest |after - before| of every
numeric column over the field's rows, beside the largest |field - reference| of the same column in
BEFORE (the field's difference to the exact field, mu_r and discretization together). For radius.csv
also the largest |after - before| of mc_p99_pp_deg in units of the Monte Carlo's own error of p99,
estimated per row as 0.05 (p99 - p95) (the 95 % binomial interval of the 99th percentile of 10^4
samples spans order statistics 9900 +- 20: docs/benchmarks.md). radius_recommendation.csv: every row
of the field, before and after.
"""
import argparse
import csv
import math
import os


def rows(path, field):
    with open(path) as f:
        return [r for r in csv.DictReader(f) if r["field"] == field]


def num(v):
    try:
        return float(v)
    except ValueError:
        return None


def key(r, cols):
    return tuple(r[c] for c in cols)


def compare(before, after, ref, keys, title):
    print(f"\n{title}: {len(after)} rows")
    A = {key(r, keys): r for r in after}
    R = {key(r, [k for k in keys]): r for r in ref}
    cols = [c for c in before[0] if c not in keys and num(before[0][c]) is not None]
    print(f"  {'column':28s} {'max|after-before|':>18s} {'max|field-ref|':>16s}")
    for c in cols:
        d = dref = 0.0
        for b in before:
            a = A.get(key(b, keys))
            if a is None:
                continue
            x, y = num(a[c]), num(b[c])
            if x is not None and y is not None and math.isfinite(x) and math.isfinite(y):
                d = max(d, abs(x - y))
            kr = key(b, keys)
            rr = R.get(kr)
            if rr is not None and num(rr[c]) is not None and math.isfinite(num(rr[c])) and y is not None and math.isfinite(y):
                dref = max(dref, abs(y - num(rr[c])))
        print(f"  {c:28s} {d:18.3e} {dref:16.3e}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--field", default="fem")
    ap.add_argument("--reference", default="analytic")
    o = ap.parse_args()
    p = lambda d, f: os.path.join(d, f)
    for name, keys in (("radius.csv", ["array", "r0_mm"]), ("radius_spectra.csv", ["array", "r0_mm", "case"]),
                       ("radius_budget.csv", ["array", "group"])):
        b, a = rows(p(o.before, name), o.field), rows(p(o.after, name), o.field)
        ref = rows(p(o.before, name), o.reference)
        if name == "radius_budget.csv":  # budget rows are at each field's own recommended r0
            pass
        compare(b, a, ref, keys, f"{name} ({o.field})")
        if name == "radius.csv":
            A = {key(r, keys): r for r in a}
            worst = (0.0, None)
            for r in b:
                q = A[key(r, keys)]
                err = 0.05 * (float(r["mc_p99_pp_deg"]) - float(r["mc_p95_pp_deg"]))
                if err > 0:
                    z = abs(float(q["mc_p99_pp_deg"]) - float(r["mc_p99_pp_deg"])) / err
                    if z > worst[0]:
                        worst = (z, (r["array"], r["r0_mm"], float(q["mc_p99_pp_deg"]) - float(r["mc_p99_pp_deg"]), err))
            print(f"  largest |d p99| / (0.05 (p99 - p95)): {worst[0]:.3f} at {worst[1]}")
    print("\nradius_recommendation.csv")
    for b, a in zip(rows(p(o.before, "radius_recommendation.csv"), o.field),
                    rows(p(o.after, "radius_recommendation.csv"), o.field)):
        print(f"  {b['array']:7s} r0 {b['r0_best_mm']} -> {a['r0_best_mm']}, total p99 {b['total_p99_pp_deg']} -> "
              f"{a['total_p99_pp_deg']}, band {b['band_lo_mm']}..{b['band_hi_mm']} -> {a['band_lo_mm']}..{a['band_hi_mm']}")


if __name__ == "__main__":
    main()
