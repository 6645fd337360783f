#!/usr/bin/env python3
"""Bz of solve_field's plane.vti as rows "x y z Bz" (mm, T), the input of
fem_vs_exact --other-bz (scripts/bench_getdp.sh). Reads the file as solve_field
writes it: VTK XML image data, one piece, raw appended data (not compressed,
not base64), a Float64 point array Bz. Anything else: one line, exit 2."""
import re
import struct
import sys


def fail(msg):
    sys.stderr.write("plane_bz.py: %s: %s\n" % (sys.argv[1] if len(sys.argv) > 1 else "?", msg))
    sys.exit(2)


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: plane_bz.py DIR/plane.vti > bz.txt\n")
        sys.exit(2)
    try:
        data = open(sys.argv[1], "rb").read()
    except OSError as e:
        fail("cannot read (%s)" % e.strerror)
    at = data.find(b"<AppendedData")
    if at < 0:
        fail("no appended data (allowed: solve_field's plane.vti)")
    head = data[:at].decode("utf-8", "replace")
    if "compressor=" in head or 'encoding="raw"' not in data[at:at + 200].decode("utf-8", "replace"):
        fail("compressed or base64 data (allowed: raw, output.compress = false)")

    def attr(name):
        m = re.search(name + r'="([^"]+)"', head)
        if not m:
            fail("no %s attribute" % name)
        return m.group(1)

    hsize = {"UInt32": 4, "UInt64": 8}.get(attr("header_type"))
    if hsize is None:
        fail("header_type must be UInt32 or UInt64")
    ext = [int(v) for v in attr("WholeExtent").split()]
    org = [float(v) for v in attr("Origin").split()]
    spc = [float(v) for v in attr("Spacing").split()]
    m = re.search(r'<DataArray type="Float64" Name="Bz"[^>]*offset="(\d+)"', head)
    if len(ext) != 6 or len(org) != 3 or len(spc) != 3 or not m or ext[4] != ext[5]:
        fail("not a plane with a Float64 array Bz")
    nx, ny = ext[1] - ext[0] + 1, ext[3] - ext[2] + 1
    base = data.index(b"_", at) + 1 + int(m.group(1))
    block = data[base:base + hsize]
    if len(block) != hsize:
        fail("truncated data")
    nbytes = struct.unpack("<Q" if hsize == 8 else "<I", block)[0]
    if nbytes != 8 * nx * ny or base + hsize + nbytes > len(data):
        fail("Bz has %d bytes, expected %d" % (nbytes, 8 * nx * ny))
    bz = struct.unpack("<%dd" % (nx * ny), data[base + hsize:base + hsize + nbytes])
    out = []
    for j in range(ny):
        for i in range(nx):
            out.append("%.6f %.6f %.6f %.17g\n" % (org[0] + (ext[0] + i) * spc[0], org[1] + (ext[2] + j) * spc[1],
                                                  org[2], bz[j * nx + i]))
    sys.stdout.write("".join(out))


main()
