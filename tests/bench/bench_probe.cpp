// bench_probe: throughput of the probe-path library (Google Benchmark; not a
// ctest test). Run: build/bin/bench_probe [--benchmark_filter=...]
//   ExactFieldBz   exact-field B_z samples/s, batch call (OpenMP, all cores),
//                  points on the study's sensing plane z = 4.55 mm, r in [1, 4] mm
//   ExactFieldB    the same for the full vector B
//   MountingCase   error_spectrum cases/s on the exact field, 3600 steps,
//                  arrays `two` and `ring:8` (static + dynamic eccentricity)
#include <benchmark/benchmark.h>

#include <cmath>

#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "core/units.hpp"

namespace {

// n points on the sensing plane, deterministic (golden-angle spiral in r in [1, 4] mm).
Eigen::Matrix3Xd plane_points(int n, double z_mm) {
  Eigen::Matrix3Xd p(3, n);
  for (int i = 0; i < n; ++i) {
    const double r = 1.0 + 3.0 * (i + 0.5) / n, a = i * 2.399963229728653;
    p.col(i) << r * std::cos(a), r * std::sin(a), z_mm;
  }
  return p;
}

void ExactFieldBz(benchmark::State& state) {
  const magenc::AnalyticField f{magenc::Magnet{}};
  const Eigen::Matrix3Xd p = plane_points(static_cast<int>(state.range(0)), 4.55);
  for (auto _ : state) benchmark::DoNotOptimize(f.Bz_T(p).data());
  state.SetItemsProcessed(state.iterations() * p.cols());
}
BENCHMARK(ExactFieldBz)->Arg(1 << 17)->UseRealTime()->Unit(benchmark::kMillisecond);

void ExactFieldB(benchmark::State& state) {
  const magenc::AnalyticField f{magenc::Magnet{}};
  const Eigen::Matrix3Xd p = plane_points(static_cast<int>(state.range(0)), 4.55);
  for (auto _ : state) benchmark::DoNotOptimize(f.B_T(p).data());
  state.SetItemsProcessed(state.iterations() * p.cols());
}
BENCHMARK(ExactFieldB)->Arg(1 << 17)->UseRealTime()->Unit(benchmark::kMillisecond);

void MountingCase(benchmark::State& state, const char* array) {
  const magenc::AnalyticField f{magenc::Magnet{}};
  magenc::ProbeSetup setup;
  setup.array = magenc::ProbeArray::parse(array);
  setup.steps = 3600;
  magenc::Mount m;
  m.sx_mm = 0.03;
  m.dx_mm = 0.05;
  for (auto _ : state) benchmark::DoNotOptimize(magenc::error_spectrum(f, setup, m).c_deg[1]);
  state.SetItemsProcessed(state.iterations());  // items = mounting cases
}
BENCHMARK_CAPTURE(MountingCase, two, "two")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCase, ring8, "ring:8")->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
