"""magenc: angle error of magnetic rotary encoders (the library behind the executables).

Lengths in mm, angles in degrees, fields in tesla; points in the magnet frame (magnet at rest,
centred at the origin, axis z). Configuration keys as a dict {"mount.sx_mm": 0.1} or keyword
arguments (mount_sx_mm=0.1), the same keys as --set; a bad key or value raises ValueError
(magenc.InputError) with the executables' one-line message. Field sources: "analytic" (exact
field of the [magnet] keys), "fem:DIR" (a solve_field output), "grid:FILE.vti", "table:FILE",
"linear". Type stubs ship with the package (py.typed).
"""
from ._magenc import ComputeError as ComputeError
from ._magenc import InputError as InputError
from ._magenc import angle_error as angle_error
from ._magenc import calibrate as calibrate
from ._magenc import config_keys as config_keys
from ._magenc import diagnose as diagnose
from ._magenc import field_at as field_at
from ._magenc import inspect as inspect
from ._magenc import spectrum as spectrum

__all__ = ["ComputeError", "InputError", "angle_error", "calibrate", "config_keys", "diagnose", "field_at",
           "inspect", "spectrum"]
