#!/usr/bin/env python3
"""Load test of serve on localhost (docs/benchmarks.md "serve"): N what-ifs, one after another on one
keep-alive connection, latency percentiles per kind; every tenth request is bad input, which must be
answered 400 with a one-line error while the server keeps running. Seeded; bounded (N requests, 127.0.0.1).

Usage: scripts/bench_serve.py [--bin build/bin] [--n 1000] [--seed 1]
Prints the table of docs/benchmarks.md and the server's peak RSS (from /proc, Linux).
"""
import argparse
import http.client
import json
import pathlib
import random
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "serve"))
from serve_process import running_serve  # noqa: E402

BAD = ["mount.dx_mm=abc", "mount.sx=1", "sensor.steps=3", "sensor.array=ring:2", "magnet.inner_radius_mm=5",
       "no equals sign", "mount.tilt_x_deg=90", "sensor.principle=inplane\nsensor.array=diff4", "\x01=\x02",
       "calibration.method=lut:1"]


def whatifs(n, rng):
    """(kind, body): the default magnet with random mounts; a ring with a side-shaft sensor; bad input."""
    for i in range(n):
        if i % 10 == 9:
            yield "bad input", rng.choice(BAD)
            continue
        mount = "\n".join(f"mount.{k}_mm={rng.uniform(-0.1, 0.1):.4f}" for k in ("sx", "sy", "dx", "dy"))
        if i % 10 == 8:
            yield "ring, side-shaft inplane", ("magnet.radius_mm=16\nmagnet.inner_radius_mm=11\n"
                                               "sensor.principle=inplane\nsensor.array=point\n"
                                               "sensor.center_mm=18,0\nsensor.plane_height_mm=-2\n"
                                               "sensor.direction=auto\nsensor.zero_deg=auto\nmount.sx_mm=0.05")
        else:
            yield "default magnet, two", mount + f"\nmount.dz_mm={rng.uniform(-0.2, 0.2):.4f}"


def rss_peak_kb(pid):
    for line in pathlib.Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1])
    return -1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=str(ROOT / "build" / "bin"))
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    times = {}
    with running_serve(pathlib.Path(a.bin) / "serve") as url:
        host, port = url.split("//")[1].strip("/").split(":")
        conn = http.client.HTTPConnection(host, int(port), timeout=30)
        for kind, body in whatifs(a.n, rng):
            t0 = time.perf_counter()
            conn.request("POST", "/api/whatif", body=body.encode())
            r = conn.getresponse()
            answer = json.loads(r.read())
            times.setdefault(kind, []).append(1e3 * (time.perf_counter() - t0))
            if kind == "bad input":
                assert r.status == 400 and not answer["ok"] and "\n" not in answer["error"], (body, answer)
            else:
                assert r.status == 200 and answer["ok"], (body, answer)
        exe = str(pathlib.Path(a.bin) / "serve").encode()
        pid = [p.name for p in pathlib.Path("/proc").iterdir()
               if p.name.isdigit() and (p / "cmdline").exists() and (p / "cmdline").read_bytes().startswith(exe)]
        rss = rss_peak_kb(pid[0]) if pid else -1
        conn.request("POST", "/api/whatif", body=b"")
        assert conn.getresponse().status == 200, "the server stopped answering"
    print(f"{a.n} what-ifs, seed {a.seed}, serve's peak RSS {rss / 1024:.0f} MB")
    print("| what-if | n | p50 (ms) | p90 (ms) | p99 (ms) | max (ms) |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for kind, t in times.items():
        t = sorted(t)
        q = lambda p: t[min(len(t) - 1, int(p * len(t)))]  # noqa: E731
        print(f"| {kind} | {len(t)} | {q(0.5):.1f} | {q(0.9):.1f} | {q(0.99):.1f} | {t[-1]:.1f} |")


if __name__ == "__main__":
    main()
