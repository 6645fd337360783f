"""magenc from Python, as a notebook session would use it.

Run from the repository root after scripts/build.sh:
    export PYTHONPATH=$PWD/build/python
    python3 docs/python_example.py
Lengths in mm, angles in degrees, fields in tesla; points in the magnet frame
(magnet at rest, centred at the origin, axis z; the default sensing plane is z = 4.55 mm).
"""
import numpy as np

import magenc

np.set_printoptions(precision=6, suppress=False, linewidth=100)

# %% 1. B along a line through the magnet: the exact field, inside the magnet too.
z = np.array([-3.0, -1.0, 0.0, 1.0, 3.0, 4.55])
B = magenc.field_at(np.column_stack([np.zeros_like(z), np.zeros_like(z), z]))
print("1. default magnet (R 2 mm, L 4 mm, Br 1.2 T, diametric along x), B on the axis:")
for zi, b in zip(z, B):
    print(f"   z = {zi:5.2f} mm   Bx = {b[0]: .6f} T   By = {b[1]: .1e}   Bz = {b[2]: .1e}")

# %% 2. Any size and polarization direction: a 6 x 3 mm magnet polarized 20 deg out of its plane.
tilted = {"magnet.radius_mm": 3.0, "magnet.height_mm": 3.0, "magnet.magnetization_deg": 30.0,
          "magnet.magnetization_elevation_deg": 20.0}
B = magenc.field_at([[1.0, 0.5, 3.0], [0.0, 0.0, 0.0]], config=tilted)
print("2. tilted polarization, B at (1, 0.5, 3) mm and at the centre (T):")
print("  ", B[0], "\n  ", B[1])

# %% 3. Angle error of an eccentric mount, and its spectrum (the numbers error_spectrum prints).
theta, eps = magenc.angle_error(array="two", config={"mount.dx_mm": 0.1})
s = magenc.spectrum(eps)
print(f"3. two probes, dx = 0.1 mm: {len(theta)} samples, c1 = {s['c1_deg']:.6f} deg, "
      f"c2 = {s['c2_deg']:.6f} deg, pp = {s['pp_deg']:.6f} deg")

# %% 4. Keyword arguments carry the same keys: a sweep of the static eccentricity for a diff4 array.
print("4. diff4, sx sweep (mm -> c1 deg):")
for sx in [0.0, 0.05, 0.1, 0.2]:
    _, eps = magenc.angle_error(array="diff4", mount_sx_mm=sx)
    print(f"   sx = {sx:4.2f}   c1 = {magenc.spectrum(eps)['c1_deg']:.3e}")

# %% 5. Back from a measured curve to its cause: a synthetic "measurement" of sx = 0.04, dx = 0.06 mm.
theta, eps = magenc.angle_error(config={"mount.sx_mm": 0.04, "mount.dx_mm": 0.06, "sensor.steps": 360})
rng = np.random.default_rng(1)
eps_measured = eps + rng.normal(0.0, 0.002, eps.shape)  # 2 mdeg reference-encoder noise
with open("/tmp/magenc_example_curve.csv", "w") as f:
    f.write("theta_deg,error_deg\n")
    f.writelines(f"{t:.9g},{e:.9g}\n" for t, e in zip(theta, eps_measured))
fit = magenc.diagnose("/tmp/magenc_example_curve.csv", free=["sx", "dx"])
print("5. diagnose (fit.json as a dict):")
for name in ("sx_mm", "dx_mm"):
    p = fit["parameters"][name]
    print(f"   {name} = {p['value']:.5f} +- {p['sigma']:.5f} mm")
print(f"   residual RMS {fit['residual_rms_deg']:.5f} deg")

# %% 6. Bad input raises ValueError with the executables' one-line message.
for bad in (lambda: magenc.field_at([[0.0, 0.0, 2.0]]),            # on the top face
            lambda: magenc.angle_error(config={"mount.sx": 0.1})):  # unknown key
    try:
        bad()
    except ValueError as e:
        print("6. ValueError:", e)
