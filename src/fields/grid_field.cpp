#include "fields/grid_field.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace magenc {

Interp parse_interp(const std::string& s, const std::string& what) {
  if (s == "nearest") return Interp::Nearest;
  if (s == "linear") return Interp::Linear;
  if (s == "cubic") return Interp::Cubic;
  throw InputError(what + " = '" + s + "' is not allowed: one of nearest, linear, cubic");
}

std::string interp_name(Interp mode) {
  switch (mode) {
    case Interp::Nearest: return "nearest";
    case Interp::Linear: return "linear";
    case Interp::Cubic: return "cubic";
  }
  return "?";
}

namespace {

std::string point_text(const Vec3& p) {
  return "(" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + ") mm";
}

// Tolerance, in cells, for points that rounding puts just outside the grid.
constexpr double kCellTol = 1e-9;

// Nodes and weights of the 1-D interpolation stencil along one axis.
template <Interp M>
struct AxisStencil {
  static constexpr int W = M == Interp::Nearest ? 1 : (M == Interp::Linear ? 2 : 4);
  int i0;       // first node of the stencil
  double w[W];  // weights of nodes i0 .. i0+W-1
};

// t: position in cell units from node 0 (already known to be within
// [-kCellTol, n-1+kCellTol]); n: nodes along the axis (>= W).
template <Interp M>
inline AxisStencil<M> axis_stencil(double t, int n) {
  AxisStencil<M> a;
  t = std::clamp(t, 0.0, double(n - 1));
  if constexpr (M == Interp::Nearest) {
    a.i0 = int(t + 0.5);
    a.w[0] = 1.0;
  } else if constexpr (M == Interp::Linear) {
    const int i = std::min(int(t), n - 2);
    const double f = t - i;
    a.i0 = i;
    a.w[0] = 1.0 - f;
    a.w[1] = f;
  } else {
    // 4-point Lagrange on nodes i-1, i, i+1, i+2; f = t - i in [0,1) inside,
    // in [-1,0) or [1,2] where the stencil is shifted at the grid's edges.
    const int i = std::clamp(int(t), 1, n - 3);
    const double f = t - i;
    const double fm1 = f - 1.0, fm2 = f - 2.0, fp1 = f + 1.0;
    a.i0 = i - 1;
    a.w[0] = -f * fm1 * fm2 * (1.0 / 6.0);
    a.w[1] = fp1 * fm1 * fm2 * 0.5;
    a.w[2] = -fp1 * f * fm2 * 0.5;
    a.w[3] = fp1 * f * fm1 * (1.0 / 6.0);
  }
  return a;
}

// Grid geometry in the form the kernels use.
struct Geo {
  double o[3];    // origin (mm)
  double ih[3];   // 1/spacing (1/mm)
  int n[3];       // nodes per axis
  std::ptrdiff_t nx, nxy;
};

// Interpolates C arrays (same grid) at p: out[c] = sum w * v[c][node].
template <Interp M, bool Is3D, int C>
inline void interpolate(const Geo& g, const double* const* v, const double* p, double* out) {
  using S = AxisStencil<M>;
  const S ax = axis_stencil<M>((p[0] - g.o[0]) * g.ih[0], g.n[0]);
  const S ay = axis_stencil<M>((p[1] - g.o[1]) * g.ih[1], g.n[1]);
  for (int c = 0; c < C; ++c) out[c] = 0.0;
  auto plane = [&](std::ptrdiff_t base, double wz) {
    for (int b = 0; b < S::W; ++b) {
      const std::ptrdiff_t row = base + (ay.i0 + b) * g.nx + ax.i0;
      for (int c = 0; c < C; ++c) {
        double s = 0.0;
        for (int a = 0; a < S::W; ++a) s += ax.w[a] * v[c][row + a];
        out[c] += wz * ay.w[b] * s;
      }
    }
  };
  if constexpr (Is3D) {
    const S az = axis_stencil<M>((p[2] - g.o[2]) * g.ih[2], g.n[2]);
    for (int k = 0; k < S::W; ++k) plane((az.i0 + k) * g.nxy, az.w[k]);
  } else {
    plane(0, 1.0);
  }
}

// A NaN coordinate is outside. The comparisons are the quiet ones (std::isgreaterequal,
// std::islessequal): a plain >= or <= with a NaN operand raises FE_INVALID, which Debug builds trap
// (fp_trap.hpp), while NaN points are expected input here (they must become an InputError).
inline bool inside(const Geo& g, bool is3d, const double* p) {
  for (int d = 0; d < 2 + int(is3d); ++d) {
    const double t = (p[d] - g.o[d]) * g.ih[d];
    if (!(std::isgreaterequal(t, -kCellTol) && std::islessequal(t, g.n[d] - 1 + kCellTol))) return false;
  }
  if (!is3d && !std::islessequal(std::abs(p[2] - g.o[2]), GridField::kPlaneTolerance_mm)) return false;
  return true;
}

Geo make_geo(const GridData& g) {
  Geo geo{};
  for (int d = 0; d < 3; ++d) {
    geo.o[d] = g.origin_mm[d];
    geo.ih[d] = 1.0 / g.spacing_mm[d];
    geo.n[d] = g.dims[d];
  }
  geo.nx = g.dims[0];
  geo.nxy = std::ptrdiff_t(g.dims[0]) * g.dims[1];
  return geo;
}

// Batch loop: out is C x N (column-major); returns index of the first point
// outside the grid, or N when all are inside.
template <Interp M, bool Is3D, int C>
Eigen::Index batch(const Geo& g, const double* const* v, const Eigen::Matrix3Xd& p, double* out) {
  const Eigen::Index n = p.cols();
  const double* pp = p.data();
  Eigen::Index first_bad = n;
#pragma omp parallel for schedule(static) reduction(min : first_bad)
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* q = pp + 3 * i;
    if (!inside(g, Is3D, q)) {
      first_bad = std::min(first_bad, i);
      continue;
    }
    interpolate<M, Is3D, C>(g, v, q, out + C * i);
  }
  return first_bad;
}

template <int C>
Eigen::Index dispatch(Interp mode, bool is3d, const Geo& g, const double* const* v,
                      const Eigen::Matrix3Xd& p, double* out) {
  switch (mode) {
    case Interp::Nearest:
      return is3d ? batch<Interp::Nearest, true, C>(g, v, p, out) : batch<Interp::Nearest, false, C>(g, v, p, out);
    case Interp::Linear:
      return is3d ? batch<Interp::Linear, true, C>(g, v, p, out) : batch<Interp::Linear, false, C>(g, v, p, out);
    case Interp::Cubic:
      return is3d ? batch<Interp::Cubic, true, C>(g, v, p, out) : batch<Interp::Cubic, false, C>(g, v, p, out);
  }
  return 0;
}

}  // namespace

GridData sample_grid(const FieldSource& field, const Vec3& origin_mm, const Vec3& spacing_mm,
                     const std::array<int, 3>& dims, bool bz_only) {
  GridData g;
  g.origin_mm = origin_mm;
  g.spacing_mm = spacing_mm;
  g.dims = dims;
  g.source = "sampled " + field.name() + " field";
  const std::size_t n = g.nodes();
  const Eigen::Matrix3Xd p = g.points_mm();
  if (bz_only) {
    const Eigen::VectorXd bz = field.Bz_T(p);
    g.Bz_T.assign(bz.data(), bz.data() + n);
  } else {
    g.set_B(field.B_T(p));
  }
  g.validate();
  return g;
}

GridField::GridField(GridData grid, Interp mode, std::string name)
    : grid_(std::move(grid)), mode_(mode), name_(std::move(name)) {
  grid_.validate();
  const int need = mode_ == Interp::Nearest ? 1 : (mode_ == Interp::Linear ? 2 : 4);
  for (int d = 0; d < (grid_.is_plane() ? 2 : 3); ++d)
    if (grid_.dims[d] < need)
      throw InputError("grid " + grid_.source + ": " + std::to_string(grid_.dims[d]) + " nodes along axis " +
                       std::to_string(d) + " are too few for --interp " + interp_name(mode_) + " (needs >= " +
                       std::to_string(need) + ")");
}

std::shared_ptr<GridField> GridField::from_file(const std::filesystem::path& file, Interp mode) {
  return std::make_shared<GridField>(read_grid_vti(file), mode);
}

bool GridField::contains(const Vec3& p_mm) const {
  const Geo g = make_geo(grid_);
  return inside(g, !grid_.is_plane(), p_mm.data());
}

std::string GridField::extent_text() const {
  const auto& g = grid_;
  auto range = [&](int d) {
    std::string r = "[";  // not "[" + std::string: GCC 12 -Wrestrict false positive (GCC bug 105651)
    r += num(g.origin_mm[d]) + ", " + num(g.origin_mm[d] + (g.dims[d] - 1) * g.spacing_mm[d]) + "] mm";
    return r;
  };
  std::string s = "x in " + range(0) + ", y in " + range(1);
  if (g.is_plane())
    s += ", z = " + num(g.origin_mm.z()) + " mm (2-D plane)";
  else
    s += ", z in " + range(2);
  return s;
}

void GridField::throw_outside(const Vec3& p) const {
  const auto& g = grid_;
  if (g.is_plane() && !std::islessequal(std::abs(p.z() - g.origin_mm.z()), kPlaneTolerance_mm))  // quiet: p may be NaN
    throw InputError(name_ + " " + g.source + ": point " + point_text(p) + " is off the " + name_ + "'s plane z = " +
                     num(g.origin_mm.z()) + " mm: a 2-D " + name_ + " serves only dz = 0 (no tilts); " +
                     (name_ == "table" ? "give a z column with several levels" : "use box.vti") +
                     " for air-gap offsets");
  throw InputError(name_ + " " + g.source + ": point " + point_text(p) + " is outside the sampled region " + extent_text() +
                   "; grids are never extrapolated: enlarge the grid or reduce r0 and the offsets");
}

void GridField::require_B() const {
  if (!grid_.has_B())
    throw InputError("grid " + grid_.source + " holds only Bz (no point array `B`): B cannot be evaluated");
}

double GridField::Bz_T(const Vec3& p_mm) const {
  const Geo g = make_geo(grid_);
  const bool is3d = !grid_.is_plane();
  if (!inside(g, is3d, p_mm.data())) throw_outside(p_mm);
  const double* v[1] = {grid_.Bz_T.data()};
  double out[1] = {0.0};
  switch (mode_) {
    case Interp::Nearest:
      is3d ? interpolate<Interp::Nearest, true, 1>(g, v, p_mm.data(), out)
           : interpolate<Interp::Nearest, false, 1>(g, v, p_mm.data(), out);
      break;
    case Interp::Linear:
      is3d ? interpolate<Interp::Linear, true, 1>(g, v, p_mm.data(), out)
           : interpolate<Interp::Linear, false, 1>(g, v, p_mm.data(), out);
      break;
    case Interp::Cubic:
      is3d ? interpolate<Interp::Cubic, true, 1>(g, v, p_mm.data(), out)
           : interpolate<Interp::Cubic, false, 1>(g, v, p_mm.data(), out);
      break;
  }
  return out[0];
}

Vec3 GridField::B_T(const Vec3& p_mm) const {
  require_B();
  Eigen::Matrix3Xd p(3, 1);
  p.col(0) = p_mm;
  return B_T(p).col(0);
}

Eigen::VectorXd GridField::Bz_T(const Eigen::Matrix3Xd& p_mm) const {
  const Geo g = make_geo(grid_);
  const double* v[1] = {grid_.Bz_T.data()};
  Eigen::VectorXd out(p_mm.cols());
  const Eigen::Index bad = dispatch<1>(mode_, !grid_.is_plane(), g, v, p_mm, out.data());
  if (bad < p_mm.cols()) throw_outside(p_mm.col(bad));
  return out;
}

Eigen::Matrix3Xd GridField::B_T(const Eigen::Matrix3Xd& p_mm) const {
  require_B();
  const Geo g = make_geo(grid_);
  const double* v[3] = {grid_.Bx_T.data(), grid_.By_T.data(), grid_.Bz_T.data()};
  Eigen::Matrix3Xd out(3, p_mm.cols());
  const Eigen::Index bad = dispatch<3>(mode_, !grid_.is_plane(), g, v, p_mm, out.data());
  if (bad < p_mm.cols()) throw_outside(p_mm.col(bad));
  return out;
}

}  // namespace magenc
