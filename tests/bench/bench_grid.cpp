// bench_grid: GridField sampling throughput (Google Benchmark; not a ctest
// test). Run: build/bin/bench_grid. Points on the probe-circle annulus of the
// default sensing plane; grid = solve_field's default plane (h = 0.05 mm,
// [-5, 5] mm) or box (h = 0.05 mm, 21 layers); all OpenMP threads.
// Recorded 2026-11-21, OMP_NUM_THREADS=2, Release -O3 -march=native, on a
// 2-core machine shared with other builds (so a lower bound), Bz samples/s:
//   plane nearest 62 M, plane linear 64 M, plane cubic 30 M (aim: 20 M),
//   box trilinear 28 M, box tricubic 9.9 M (below the 20 M aim: 64-node stencil).
#include <benchmark/benchmark.h>

#include <cmath>

#include "fields/grid_field.hpp"

namespace {

class Smooth final : public magenc::FieldSource {
 public:
  std::string name() const override { return "smooth"; }
  magenc::Vec3 B_T(const magenc::Vec3& p) const override { return {0, 0, Bz_T(p)}; }
  double Bz_T(const magenc::Vec3& p) const override { return std::sin(p.x()) * std::cos(p.y()) / (1 + 0.1 * p.z()); }
  using FieldSource::B_T;
  using FieldSource::Bz_T;
};

Eigen::Matrix3Xd annulus(int n, double z, double dz_span) {
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i) {
    const double r = 2.0 + 1.0 * (i + 0.5) / n, a = i * 2.399963229728653;
    p.col(i) << r * std::cos(a), r * std::sin(a), z + dz_span * ((i % 101) / 100.0 - 0.5);
  }
  return p;
}

void GridBz(benchmark::State& state, magenc::Interp mode, bool box) {
  const Smooth f;
  const magenc::GridData g = box ? magenc::sample_grid(f, {-4, -4, 4.05}, {0.05, 0.05, 0.05}, {161, 161, 21}, true)
                                 : magenc::sample_grid(f, {-5, -5, 4.55}, {0.05, 0.05, 0.05}, {201, 201, 1}, true);
  const magenc::GridField field(g, mode);
  const Eigen::Matrix3Xd p = annulus(1 << 20, 4.55, box ? 0.9 : 0.0);
  for (auto _ : state) benchmark::DoNotOptimize(field.Bz_T(p).data());
  state.SetItemsProcessed(state.iterations() * p.cols());
}
BENCHMARK_CAPTURE(GridBz, plane_nearest, magenc::Interp::Nearest, false)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(GridBz, plane_linear, magenc::Interp::Linear, false)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(GridBz, plane_cubic, magenc::Interp::Cubic, false)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(GridBz, box_linear, magenc::Interp::Linear, true)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(GridBz, box_cubic, magenc::Interp::Cubic, true)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
