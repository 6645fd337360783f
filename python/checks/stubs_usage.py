"""A typical use of magenc, type-checked against the package's stubs by `mypy --strict` (ctest python_stubs_mypy).

mypy must accept it; python/checks/stubs_misuse.py holds calls the stubs must reject.
"""
import numpy as np
import numpy.typing as npt

import magenc

points_mm: npt.NDArray[np.float64] = np.array([[2.4, 0.0, 4.55], [0.0, 2.4, 4.55]])
B_T: npt.NDArray[np.float64] = magenc.field_at(points_mm, config={"magnet.radius_mm": 2.0}, mount_sx_mm=0.0)
theta_deg, eps_deg = magenc.angle_error(array="diff4", config={"mount.dx_mm": 0.1})
coefficients: dict[str, float] = magenc.spectrum(eps_deg)
c1_deg: float = coefficients["c1_deg"]
keys: list[dict[str, str]] = magenc.config_keys()
try:
    magenc.field_at([[0.0, 0.0, 2.0]])
except magenc.InputError as e:
    message: str = str(e)
print(B_T.shape, float(theta_deg[1]), c1_deg, len(keys))
