// GridField: interpolation exactness, convergence rates, region checks, .vti I/O.
//
// Checks (each implemented below):
//  1. nearest returns node values at nodes; linear reproduces fields linear in
//     each coordinate (bi-/trilinear) exactly; cubic reproduces polynomials of
//     degree <= 3 per coordinate exactly, including the edge cells where the
//     stencil is shifted inward.
//  2. Rates on a smooth field as the spacing halves: nearest ~1, linear ~2,
//     cubic ~4 (max error over random points).
//  3. A point outside the grid (or off a 2-D grid's plane) is an InputError
//     naming the source, the point and the extent (box.vti hint for planes);
//     never extrapolated. A batch with one bad point throws too.
//  4. Batch and single-point evaluations agree; results do not depend on the
//     thread count.
//  5. .vti round trip (write_grid_vti -> read_grid_vti -> GridField) is exact;
//     files without B/Bz, missing files, too-small grids are InputErrors.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <unistd.h>
#include <omp.h>
#include <random>

#include "core/errors.hpp"
#include "fields/grid_field.hpp"

using namespace magenc;

namespace {

// A FieldSource from a lambda (Bz only; Bx, By = derivatives-free placeholders).
template <class F>
class FnField final : public FieldSource {
 public:
  explicit FnField(F f) : f_(f) {}
  std::string name() const override { return "test"; }
  Vec3 B_T(const Vec3& p) const override { return {0.5 * f_(p), -0.25 * f_(p), f_(p)}; }
  double Bz_T(const Vec3& p) const override { return f_(p); }
  using FieldSource::B_T;
  using FieldSource::Bz_T;

 private:
  F f_;
};
template <class F>
FnField<F> fn_field(F f) {
  return FnField<F>(f);
}

// Random points inside [lo, hi] per axis (z fixed when plane).
Eigen::Matrix3Xd random_points(int n, const Vec3& lo, const Vec3& hi, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) p(d, i) = lo[d] + (hi[d] - lo[d]) * u(rng);
  return p;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::filesystem::path temp_dir() {
  auto d = std::filesystem::temp_directory_path() / ("magenc_test_grid_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("interpolation exactness on polynomials", "[grid]") {
  const Vec3 origin(-1.3, -0.7, 4.0);
  const Vec3 h(0.1, 0.125, 0.05);
  SECTION("2-D plane") {
    const std::array<int, 3> dims{25, 20, 1};
    const Vec3 lo = origin, hi = origin + Vec3(24 * h.x(), 19 * h.y(), 0);
    const auto pts = random_points(2000, lo, hi);
    auto bilinear = fn_field([](const Vec3& p) { return 0.3 + 1.7 * p.x() - 0.9 * p.y() + 0.45 * p.x() * p.y(); });
    auto cubic = fn_field([](const Vec3& p) {
      const double x = p.x(), y = p.y();
      return 0.2 - x + 0.5 * y * y + 0.8 * x * x * x - 0.6 * x * x * y + 0.3 * x * y * y * y + 0.1 * x * x * x * y * y * y;
    });
    GridField lin(sample_grid(bilinear, origin, h, dims), Interp::Linear);
    GridField cub(sample_grid(cubic, origin, h, dims), Interp::Cubic);
    const Eigen::VectorXd zl = lin.Bz_T(pts), zc = cub.Bz_T(pts);
    double el = 0, ec = 0;
    for (int i = 0; i < pts.cols(); ++i) {
      el = std::max(el, std::abs(zl[i] - bilinear.Bz_T(Vec3(pts.col(i)))));
      ec = std::max(ec, std::abs(zc[i] - cubic.Bz_T(Vec3(pts.col(i)))));
    }
    CHECK(el < 1e-12);
    CHECK(ec < 1e-12);
    // Edge cells (shifted cubic stencil) and the far corner.
    for (const Vec3& p : {lo, hi, Vec3(lo.x() + 0.03, hi.y() - 0.01, lo.z()), Vec3(hi.x() - 0.07, lo.y() + 0.02, lo.z())}) {
      CAPTURE(p.transpose());
      CHECK(std::abs(cub.Bz_T(p) - cubic.Bz_T(p)) < 1e-12);
      CHECK(std::abs(lin.Bz_T(p) - bilinear.Bz_T(p)) < 1e-12);
    }
    // Cubic is not exact for a quartic (the test can fail).
    auto quartic = fn_field([](const Vec3& p) { return std::pow(p.x(), 4); });
    GridField q(sample_grid(quartic, origin, h, dims), Interp::Cubic);
    CHECK(std::abs(q.Bz_T(Vec3(0.05, 0.0, origin.z())) - std::pow(0.05, 4)) > 1e-7);
    // Nearest: node values at nodes.
    GridField nn(sample_grid(cubic, origin, h, dims), Interp::Nearest);
    const Vec3 node = origin + Vec3(7 * h.x(), 11 * h.y(), 0);
    CHECK(nn.Bz_T(node) == cubic.Bz_T(node));
    CHECK(nn.Bz_T(Vec3(node + Vec3(0.4 * h.x(), -0.4 * h.y(), 0))) == cubic.Bz_T(node));
  }
  SECTION("3-D box") {
    const std::array<int, 3> dims{12, 10, 8};
    const Vec3 lo = origin, hi = origin + Vec3(11 * h.x(), 9 * h.y(), 7 * h.z());
    const auto pts = random_points(2000, lo, hi);
    auto trilinear = fn_field([](const Vec3& p) {
      return 1.0 + p.x() - 2 * p.y() + 0.5 * p.z() + 0.3 * p.x() * p.y() * p.z() - 0.2 * p.y() * p.z();
    });
    auto tricubic = fn_field([](const Vec3& p) {
      const double x = p.x(), y = p.y(), z = p.z() - 4.2;
      return x * x * x * y - z * z * z + 0.7 * x * y * y * z * z + 0.2 * x * x * x * y * y * y * z * z * z;
    });
    GridField lin(sample_grid(trilinear, origin, h, dims), Interp::Linear);
    GridField cub(sample_grid(tricubic, origin, h, dims), Interp::Cubic);
    const Eigen::VectorXd zl = lin.Bz_T(pts), zc = cub.Bz_T(pts);
    const Eigen::Matrix3Xd bl = lin.B_T(pts);
    double el = 0, ec = 0, eb = 0;
    for (int i = 0; i < pts.cols(); ++i) {
      const Vec3 p = pts.col(i);
      el = std::max(el, std::abs(zl[i] - trilinear.Bz_T(p)));
      ec = std::max(ec, std::abs(zc[i] - tricubic.Bz_T(p)));
      eb = std::max(eb, (bl.col(i) - trilinear.B_T(p)).norm());
    }
    CHECK(el < 1e-12);
    CHECK(ec < 1e-12);
    CHECK(eb < 1e-12);
  }
}

TEST_CASE("convergence rates on a smooth field", "[grid]") {
  // A smooth, field-like function of x, y, z (mm).
  auto smooth = fn_field([](const Vec3& p) {
    return std::exp(-0.08 * (p.x() * p.x() + p.y() * p.y())) * std::cos(0.9 * p.x() - 0.4 * p.y()) / (1.0 + 0.2 * p.z());
  });
  const Vec3 lo(-3.0, -3.0, 4.0);
  const double L = 6.0;
  const auto pts = random_points(20000, Vec3(-2.5, -2.5, 4.1), Vec3(2.5, 2.5, 4.5));
  const Eigen::VectorXd exact = smooth.FieldSource::Bz_T(pts);
  for (const bool box : {false, true}) {
    std::map<Interp, std::vector<double>> err;
    std::vector<double> hs;
    for (const int cells : {30, 60, 120}) {
      const double h = L / cells;
      hs.push_back(h);
      const std::array<int, 3> dims{cells + 1, cells + 1, box ? 12 * cells / 30 + 1 : 1};
      Eigen::Matrix3Xd q = pts;
      if (!box) q.row(2).setConstant(lo.z());
      const Eigen::VectorXd ex = box ? exact : smooth.FieldSource::Bz_T(q);
      const GridData g = sample_grid(smooth, lo, Vec3(h, h, 0.6 / (dims[2] - 1 > 0 ? dims[2] - 1 : 1)), dims, true);
      for (Interp m : {Interp::Nearest, Interp::Linear, Interp::Cubic}) {
        GridField f(g, m);
        err[m].push_back((f.Bz_T(q) - ex).cwiseAbs().maxCoeff());
      }
    }
    const std::map<Interp, std::pair<double, double>> expected{
        {Interp::Nearest, {0.8, 1.3}}, {Interp::Linear, {1.8, 2.2}}, {Interp::Cubic, {3.6, 4.4}}};
    for (auto& [m, e] : err) {
      for (std::size_t k = 1; k < e.size(); ++k) {
        const double rate = std::log(e[k - 1] / e[k]) / std::log(hs[k - 1] / hs[k]);
        INFO((box ? "box " : "plane ") << interp_name(m) << " h " << hs[k] << " err " << e[k] << " rate " << rate);
        CHECK(rate > expected.at(m).first);
        CHECK(rate < expected.at(m).second);
      }
    }
  }
}

TEST_CASE("points outside the grid are errors, never extrapolated", "[grid][bad-input]") {
  auto f = fn_field([](const Vec3& p) { return p.x(); });
  GridData g = sample_grid(f, Vec3(-1, -1, 4.55), Vec3(0.1, 0.1, 1), {21, 21, 1});
  g.source = "output/field/plane.vti";
  for (Interp m : {Interp::Nearest, Interp::Linear, Interp::Cubic}) {
    GridField field(g, m);
    CAPTURE(interp_name(m));
    // Edges are served.
    CHECK(field.Bz_T(Vec3(1.0, -1.0, 4.55)) == Approx(1.0));
    CHECK(field.contains(Vec3(1.0, 1.0, 4.55)));
    const std::string outside = message_of([&] { field.Bz_T(Vec3(1.01, 0.0, 4.55)); });
    CHECK(outside.find("output/field/plane.vti") != std::string::npos);
    CHECK(outside.find("(1.01, 0, 4.55) mm") != std::string::npos);
    CHECK(outside.find("x in [-1, 1] mm") != std::string::npos);
    const std::string off_plane = message_of([&] { field.Bz_T(Vec3(0.0, 0.0, 4.6)); });
    CHECK(off_plane.find("box.vti") != std::string::npos);
    CHECK(off_plane.find("4.6") != std::string::npos);
    // One bad point in a batch throws.
    Eigen::Matrix3Xd p = random_points(1000, Vec3(-0.9, -0.9, 4.55), Vec3(0.9, 0.9, 4.55));
    CHECK_NOTHROW(field.Bz_T(p));
    p(1, 517) = -1.2;
    const std::string batch = message_of([&] { field.Bz_T(p); });
    CHECK(batch.find("-1.2") != std::string::npos);
    CHECK_THROWS_AS(field.Bz_T(Vec3(std::nan(""), 0, 4.55)), InputError);
    // Only Bz stored here? No: sample_grid stored B too.
    CHECK_NOTHROW(field.B_T(Vec3(0.2, 0.3, 4.55)));
  }
  GridData bz_only = sample_grid(f, Vec3(-1, -1, 4.55), Vec3(0.1, 0.1, 1), {21, 21, 1}, true);
  CHECK_THROWS_AS(GridField(bz_only, Interp::Linear).B_T(Vec3(0, 0, 4.55)), InputError);
  // Too few nodes for the cubic stencil.
  GridData small = sample_grid(f, Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1), {3, 10, 1});
  CHECK_THROWS_AS(GridField(small, Interp::Cubic), InputError);
  CHECK_NOTHROW(GridField(small, Interp::Linear));
  CHECK_THROWS_AS(parse_interp("bicubic"), InputError);
  CHECK(parse_interp("cubic") == Interp::Cubic);
}

TEST_CASE("batch equals single points and does not depend on threads", "[grid]") {
  auto f = fn_field([](const Vec3& p) { return std::sin(p.x()) * std::cos(0.5 * p.y()) * (1 + 0.1 * p.z()); });
  GridData g = sample_grid(f, Vec3(-3, -3, 4.05), Vec3(0.05, 0.05, 0.1), {121, 121, 11});
  const auto pts = random_points(5000, Vec3(-3, -3, 4.05), Vec3(3, 3, 5.05));
  for (Interp m : {Interp::Nearest, Interp::Linear, Interp::Cubic}) {
    GridField field(g, m);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const Eigen::VectorXd one = field.Bz_T(pts);
    const Eigen::Matrix3Xd b_one = field.B_T(pts);
    omp_set_num_threads(std::max(2, threads));
    const Eigen::VectorXd many = field.Bz_T(pts);
    const Eigen::Matrix3Xd b_many = field.B_T(pts);
    omp_set_num_threads(threads);
    CHECK(one == many);
    CHECK(b_one == b_many);
    for (int i = 0; i < 50; ++i) {
      CHECK(field.Bz_T(Vec3(pts.col(i))) == one[i]);
      CHECK(field.B_T(Vec3(pts.col(i))) == b_one.col(i));
      CHECK(b_one(2, i) == Approx(one[i]).epsilon(1e-13).margin(1e-15));
    }
  }
}

TEST_CASE(".vti round trip and bad files", "[grid][io]") {
  const auto dir = temp_dir();
  auto f = fn_field([](const Vec3& p) { return 0.1 * p.x() * p.x() - p.y() + 0.01 * p.z(); });
  for (const bool plane : {true, false}) {
    const GridData g = sample_grid(f, Vec3(-2, -1.5, 4.05), Vec3(0.1, 0.125, 0.1), {41, 25, plane ? 1 : 11});
    const auto file = dir / (plane ? "plane.vti" : "box.vti");
    write_grid_vti(file, g);
    const GridData r = read_grid_vti(file);
    CHECK(r.dims == g.dims);
    CHECK((r.origin_mm - g.origin_mm).norm() < 1e-15);
    CHECK((r.spacing_mm.head<2>() - g.spacing_mm.head<2>()).norm() < 1e-15);
    CHECK(r.Bz_T == g.Bz_T);
    CHECK(r.Bx_T == g.Bx_T);
    CHECK(r.By_T == g.By_T);
    CHECK(r.source == file.string());
    auto field = GridField::from_file(file, Interp::Cubic);
    CHECK(field->Bz_T(Vec3(0.33, 0.21, 4.05)) == Approx(f.Bz_T(Vec3(0.33, 0.21, 4.05))).margin(1e-12));
    // No temporary left behind.
    int entries = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) entries += e.path().string().find(".tmp.") != std::string::npos;
    CHECK(entries == 0);
  }
  CHECK(message_of([&] { read_grid_vti(dir / "nope.vti"); }).find("nope.vti") != std::string::npos);
  {
    std::ofstream(dir / "junk.vti") << "not xml at all\n";
  }
  CHECK_THROWS_AS(read_grid_vti(dir / "junk.vti"), InputError);
  // Image data without B or Bz.
  {
    std::ofstream(dir / "noarrays.vti")
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "<ImageData WholeExtent=\"0 1 0 1 0 0\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"0 1 0 1 0 0\">\n"
           "<PointData><DataArray type=\"Float64\" Name=\"psi\" format=\"ascii\">1 2 3 4</DataArray></PointData>\n"
           "<CellData></CellData></Piece></ImageData></VTKFile>\n";
  }
  const std::string no_arrays = message_of([&] { read_grid_vti(dir / "noarrays.vti"); });
  CHECK(no_arrays.find("neither point array") != std::string::npos);
  // An ascii value that overflows: VTK rejects the array (strtod raises FE_OVERFLOW on the way,
  // untrapped while reading, fp_trap.hpp).
  {
    std::ofstream(dir / "overflow.vti")
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "<ImageData WholeExtent=\"0 1 0 1 0 0\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"0 1 0 1 0 0\">\n"
           "<PointData><DataArray type=\"Float64\" Name=\"Bz\" format=\"ascii\">1e999 0 0 0</DataArray></PointData>\n"
           "<CellData></CellData></Piece></ImageData></VTKFile>\n";
  }
  CHECK_THROWS_AS(read_grid_vti(dir / "overflow.vti"), InputError);
  std::filesystem::remove_all(dir);
}
