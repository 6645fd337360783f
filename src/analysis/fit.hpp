// Least-squares polynomial fits of a spectrum coefficient against a swept offset.
#pragma once
#include <array>
#include <Eigen/Core>

namespace magenc {

// Cubic p3*x^3 + p2*x^2 + p1*x + p0 fitted to (x, y) by least squares (QR).
// Returns {p3, p2, p1, p0}. Throws InputError with fewer than 4 distinct x.
std::array<double, 4> fit_cubic(const Eigen::VectorXd& x, const Eigen::VectorXd& y);

}  // namespace magenc
