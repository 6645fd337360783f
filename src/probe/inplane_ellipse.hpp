// The ellipse of an in-plane reading (docs/physics.md "Ring magnets and sensors off the axis"): a point
// beside a ring sees (b1, b2) = (A cos theta, -B sin theta); k = A / B sets the side-shaft error's even
// harmonics (c2 = q rad, q = (k - 1) / (k + 1)) and the gain trim that removes them.
#pragma once
#include "probe/angle_error.hpp"

namespace magenc {

// k = |A / B| from the first harmonics of b1 (its cos part) and b2 (its sin part) over the uniform turn of
// r.inplane_B_T (rows: theta samples of a whole turn; columns b1, b2).
double inplane_ellipse_k(const AngleErrorResult& r);

}  // namespace magenc
