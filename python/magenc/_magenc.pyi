"""Type stubs of the compiled module magenc._magenc (python/magenc_module.cpp).

Units: lengths in mm, angles in degrees, fields in tesla (the names say so: points_mm, eps_deg, ...).
"""
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

# A configuration value as --set takes it: a number, a bool, a string or a list of them.
_ConfigValue = Union[float, int, bool, str, Sequence[Any]]
_Config = Mapping[str, _ConfigValue]
_PathLike = Union[str, "os.PathLike[str]"]
_FloatArray = npt.NDArray[np.float64]

class InputError(ValueError):
    """Bad input: a one-line message naming the input and its allowed range."""

class ComputeError(RuntimeError):
    """A computation that could not finish (e.g. a solver that did not converge)."""

def field_at(points_mm: npt.ArrayLike, field: str = "analytic", config: Optional[_Config] = None,
             interp: str = "cubic", **keys: _ConfigValue) -> _FloatArray:
    """B in T (an (N, 3) array Bx, By, Bz) at (N, 3) points in mm in the magnet frame."""

def angle_error(field: str = "analytic", array: Optional[str] = None, config: Optional[_Config] = None,
                interp: str = "cubic", **keys: _ConfigValue) -> Tuple[_FloatArray, _FloatArray]:
    """(theta_deg, eps_deg): one turn of the configured mount, two (M,) arrays in deg."""

def spectrum(eps_deg: npt.ArrayLike, pole_pairs: int = 0) -> Dict[str, float]:
    """The spectra table's coefficients in deg: a0_deg, a1_deg..a8_deg, b1..b8, c1..c8, pp_deg; with
    pole_pairs p >= 1 (a multipole read) also ce1_deg..ce4_deg, the amplitudes of the orders p..4p."""

def diagnose(measured: Union[_PathLike, Sequence[_PathLike]], field: str = "analytic", array: Optional[str] = None,
             r0_mm: Optional[float] = None, free: Union[None, str, Sequence[str]] = None,
             config: Optional[_Config] = None, fixed_zero: bool = False, error_sign: int = 1,
             max_gap_deg: float = 30.0, starts: int = 6, seed: int = 1, cond_limit: float = 1e4,
             interp: str = "cubic", **keys: _ConfigValue) -> Dict[str, Any]:
    """diagnose's fit.json as a dict (parameters in mm and deg, residual_rms_deg)."""

def calibrate(measured: Optional[_PathLike] = None, correction: Optional[_PathLike] = None,
              method: Optional[str] = None, apply: Optional[_PathLike] = None, field: str = "analytic",
              array: Optional[str] = None, r0_mm: Optional[float] = None, config: Optional[_Config] = None,
              error_sign: int = 1, interp: str = "cubic", **keys: _ConfigValue) -> Dict[str, Any]:
    """{'source', 'correction', 'residual'}: calibrate's correction.json and residual.json (deg)."""

def inspect(scan: _PathLike, free: Union[None, str, Sequence[str]] = None, config: Optional[_Config] = None,
            cond_limit: float = 1e6, **keys: _ConfigValue) -> Dict[str, Any]:
    """inspect's fit.json as a dict (offsets in mm, rotations in deg, polarization in T)."""

def config_keys() -> List[Dict[str, str]]:
    """Every configuration key: {key, default, allowed, unit, help}."""
