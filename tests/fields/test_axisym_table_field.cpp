// AxisymmetricTableField (src/fields/axisym_table_field.*): the (r, z) tables of the exact field's parts
// against the exact field itself, point by point.
//   1. Tilted magnetization (all three parts) and a plain diametric one: B and Bz at random points of the
//      region the diagnosis fits visit (r 2.0..2.8 mm, z 2.4..2.9 mm, every azimuth) equal the direct
//      evaluation within 1e-12 of |B| (the table's tolerance; the quadrature itself is ~1e-12 relative).
//   2. Points in or next to the magnet are served directly (bit for bit the source's values).
//   3. A source without axisymmetric parts is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>

#include "core/errors.hpp"
#include "fields/analytic_field.hpp"
#include "fields/axisym_table_field.hpp"

using magenc::AnalyticField;
using magenc::AxisymmetricTableField;
using magenc::Magnet;
using magenc::Vec3;

namespace {

double worst_rel(const AxisymmetricTableField& t, const AnalyticField& f, unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ur(2.0, 2.8), uz(2.4, 2.9), ua(-3.14159, 3.14159);
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    const double r = ur(rng), z = uz(rng), a = ua(rng);
    const Vec3 p(r * std::cos(a), r * std::sin(a), z);
    const Vec3 want = f.B_T(p), got = t.B_T(p);
    worst = std::max(worst, (got - want).norm() / want.norm());
    worst = std::max(worst, std::abs(t.Bz_T(p) - f.Bz_T(p)) / want.norm());
  }
  return worst;
}

}  // namespace

TEST_CASE("axisymmetric table field equals the exact field within 1e-12", "[fields][cross-check]") {
  for (const double el : {0.0, 20.0}) {
    Magnet m;  // R = 2, L = 4, Br = 1.2 T
    m.magnetization_deg = 30.0;
    m.magnetization_elevation_deg = el;
    const auto exact = std::make_shared<AnalyticField>(m);
    const AxisymmetricTableField table(exact);
    const double w = worst_rel(table, *exact, 7, 800);
    INFO("elevation " << el << " deg: worst relative difference " << w << ", patches " << table.patches()
                      << " (direct " << table.direct_patches() << ")");
    CHECK(w < 1e-12);
    CHECK(table.patches() > 0);
    CHECK(table.direct_patches() < table.patches());
  }
  // Batch calls go through the same points.
  const auto exact = std::make_shared<AnalyticField>(Magnet{});
  const AxisymmetricTableField table(exact);
  Eigen::Matrix3Xd p(3, 3);
  p << 2.4, -1.0, 0.3, 0.1, 2.2, -2.5, 2.55, 2.6, 2.45;
  const Eigen::Matrix3Xd got = table.B_T(p), want = exact->B_T(p);
  for (Eigen::Index k = 0; k < p.cols(); ++k) CHECK((got.col(k) - want.col(k)).norm() < 1e-12 * want.col(k).norm());
}

TEST_CASE("axisymmetric table field serves points near the magnet directly", "[fields][regression]") {
  const auto exact = std::make_shared<AnalyticField>(Magnet{});
  const AxisymmetricTableField table(exact, 0.02, 7, 1e-12);
  for (const Vec3& p : {Vec3(2.01, 0.1, 1.0), Vec3(0.5, 0.5, 2.005), Vec3(1.0, 0.2, 0.0)}) {
    CHECK(table.B_T(p) == exact->B_T(p));
    CHECK(table.Bz_T(p) == exact->Bz_T(p));
  }
  CHECK(table.direct_patches() == table.patches());
}

TEST_CASE("axisymmetric table field refuses a source without parts", "[fields][bad-input]") {
  const auto lin = std::make_shared<magenc::LinearField>();
  CHECK_THROWS_AS(AxisymmetricTableField(lin), magenc::InputError);
  const auto exact = std::make_shared<AnalyticField>(Magnet{});
  CHECK_THROWS_AS(AxisymmetricTableField(exact, 0.0), magenc::InputError);
}
