"""Calls the stubs must reject (ctest python_stubs_mypy expects mypy --strict to fail on each line below)."""
import magenc

c1: str = magenc.spectrum([0.0] * 32)["c1_deg"]  # a float, not a str
magenc.angle_error(array=2)  # array is a name such as "two"
magenc.field_at()  # points_mm is required
