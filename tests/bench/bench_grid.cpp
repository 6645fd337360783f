// bench_grid: GridField sampling throughput (Google Benchmark; not a ctest
// test). Run: build/bin/bench_grid. Points on the probe-circle annulus of the
// default sensing plane; grid = solve_field's default plane (h = 0.05 mm,
// [-5, 5] mm) or box (h = 0.05 mm, 21 layers); all OpenMP threads.
// Recorded 2026-11-21, OMP_NUM_THREADS=2, Release -O3 -march=native, on a
// 2-core machine shared with other builds (so a lower bound), Bz samples/s:
//   plane nearest 62 M, plane linear 64 M, plane cubic 30 M (aim: 20 M),
//   box trilinear 28 M, box tricubic 9.9 M (below the 20 M aim: 64-node stencil).
// FemB: B of a solved FE field evaluated directly (FemField, point location in the tetrahedral mesh
// and the P2 basis), batch call, points/s. The solve_field output directory is read from
// $MAGENC_BENCH_FEM_DIR (default output/field, as ./run.sh writes it); skipped when it is missing.
//   path       probe circles: 3600 consecutive steps on each of 64 radii in [1, 4] mm at z = 4.55 mm
//   scattered  the same points in the order j -> 7919 j mod n (no two consecutive points close)
// docs/benchmarks.md gives the figures.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "field_solver/field_io/fem_field.hpp"
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

// The FE field of $MAGENC_BENCH_FEM_DIR (loaded once), or nullptr when the directory has no mesh.vtu.
const magenc::FemField* fem_field() {
  static const std::unique_ptr<magenc::FemField> f = []() -> std::unique_ptr<magenc::FemField> {
    const char* env = std::getenv("MAGENC_BENCH_FEM_DIR");
    const std::filesystem::path dir = env ? env : "output/field";
    if (!std::filesystem::exists(dir / "mesh.vtu")) return nullptr;
    return std::make_unique<magenc::FemField>(dir);
  }();
  return f.get();
}

Eigen::Matrix3Xd probe_circles(int radii, int steps, double z) {
  Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(radii) * steps);
  for (int k = 0; k < radii; ++k)
    for (int i = 0; i < steps; ++i) {
      const double r = 1.0 + 3.0 * (k + 0.5) / radii, a = 2.0 * M_PI * i / steps;
      p.col(static_cast<Eigen::Index>(k) * steps + i) << r * std::cos(a), r * std::sin(a), z;
    }
  return p;
}

void FemB(benchmark::State& state, bool path) {
  const magenc::FemField* f = fem_field();
  if (!f) {
    state.SkipWithError("no solve_field output: set MAGENC_BENCH_FEM_DIR to a directory with mesh.vtu");
    return;
  }
  const Eigen::Matrix3Xd circles = probe_circles(64, 3600, 4.55);
  Eigen::Matrix3Xd p = circles;
  if (!path)
    for (Eigen::Index j = 0; j < p.cols(); ++j) p.col(j) = circles.col((7919 * j) % p.cols());
  for (auto _ : state) benchmark::DoNotOptimize(f->B_T(p).data());
  state.SetItemsProcessed(state.iterations() * p.cols());
}
BENCHMARK_CAPTURE(FemB, path, true)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(FemB, scattered, false)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
