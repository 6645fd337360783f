# A synthetic incoming-inspection scan: the exact field of a magnet whose polarization is 1.17 T at
# 3 deg azimuth and 2 deg elevation, read by a probe offset by (0.05, -0.03, 0.08) mm and turned by
# (1, -0.5, 2) deg, 7 x 7 positions at two heights, 0.05 mT noise (seeded).
import numpy as np, magenc
rng = np.random.default_rng(7)
x, y = np.meshgrid(np.linspace(-3, 3, 7), np.linspace(-3, 3, 7))
nominal = np.concatenate([np.column_stack([x.ravel(), y.ravel(), np.full(49, z)]) for z in (4.55, 5.55)])
true = nominal + np.array([0.05, -0.03, 0.08])
B = magenc.field_at(true, config={"magnet.br_T": 1.17, "magnet.magnetization_deg": 3.0,
                                  "magnet.magnetization_elevation_deg": 2.0})
def R(a, b, c):
    a, b, c = np.radians([a, b, c])
    Rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    Ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    Rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx
reading_mT = (B @ R(1.0, -0.5, 2.0)) * 1e3 + rng.normal(0, 0.05, B.shape)   # R^T B per row
np.savetxt("scan.csv", np.column_stack([nominal, reading_mT]), delimiter=",", fmt="%.9g",
           header="x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT", comments="")
