// bench_probe: throughput of the probe-path library (Google Benchmark; not a
// ctest test). Run: build/bin/bench_probe [--benchmark_filter=...]
//   ExactFieldBz   exact-field B_z samples/s, batch call (OpenMP, all cores),
//                  points on the study's sensing plane z = 4.55 mm, r in [1, 4] mm
//   ExactFieldB    the same for the full vector B
//   MountingCase   error_spectrum cases/s on the exact field, 3600 steps,
//                  arrays `two` and `ring:8` (static + dynamic eccentricity)
//   MountingCaseChainElev  the same plus magnetization elevation 2 deg and a
//                  signal chain (offsets, gain, phase): no tilt, so the Bz path
//   MountingCaseSpeed      MountingCase at 6000 rpm with AS5045-like timing (delay 96 us, skew 2 us,
//                  filter 1 kHz, hold at 10416.67 Hz, off the 3600-step grid): the steady-state chain of
//                  probe/speed.hpp on top of the static case (docs/benchmarks.md: at most 2x)
//   FastCase/FastCaseSpeed the Monte Carlo engine's case (FastPipeline::eps with the angles as unit
//                  vectors, `two`, 360 nodes, the surrogate on the exact field): static, and at 6000 rpm
//                  with the same timing (hold) and without the hold
//   McModelBuild/McSample  the Monte Carlo engine on a 32 mm ring and on a 32-pole-pair code ring (ring:8
//                  over each; the multipole's incremental reading, MultipolePipeline) against the default
//                  magnet: the surrogate's build per design and the cost of one sample
//   MountingCaseTilted     the same plus sensor tilt (0.5, 0.3 deg) and magnet
//                  tilt 0.5 deg: every term of "Beyond the five offsets", full-B path
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "analysis/circle_field_model.hpp"
#include "analysis/fast_pipeline.hpp"
#include "probe/multipole_pipeline.hpp"
#include "probe/multipole_ring_model.hpp"
#include "fields/analytic_field.hpp"
#include "fields/multipole_field.hpp"
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

void MountingCaseSpeed(benchmark::State& state, const char* array) {
  const magenc::AnalyticField f{magenc::Magnet{}};
  magenc::ProbeSetup setup;
  setup.array = magenc::ProbeArray::parse(array);
  setup.steps = 3600;
  setup.speed.rpm = 6000;
  setup.speed.delay_us = 96;
  setup.speed.skew_us = 2;
  setup.speed.filter_hz = 1000;
  setup.speed.sample_hz = 10416.67;
  magenc::Mount m;
  m.sx_mm = 0.03;
  m.dx_mm = 0.05;
  for (auto _ : state) benchmark::DoNotOptimize(magenc::error_spectrum(f, setup, m).c_deg[1]);
  state.SetItemsProcessed(state.iterations());  // items = mounting cases
}
BENCHMARK_CAPTURE(MountingCaseSpeed, two, "two")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCaseSpeed, ring8, "ring:8")->UseRealTime()->Unit(benchmark::kMillisecond);

// hold_hz < 0: static; 0: at speed without the hold; > 0: at speed with the hold at hold_hz.
void FastCase(benchmark::State& state, double hold_hz) {
  const magenc::AnalyticField f{magenc::Magnet{}};
  const magenc::CircleFieldModel model(f, 2.4, 4.55, 360, 0.3, 0.3, 4, false);
  magenc::FastPipeline fast(model, {magenc::ProbeArray::parse("two")});
  if (hold_hz >= 0) {
    magenc::SpeedChain s;
    s.rpm = 6000;
    s.delay_us = 96;
    s.skew_us = 2;
    s.filter_hz = 1000;
    s.sample_hz = hold_hz;
    fast.set_speed(s);
  }
  magenc::ToleranceCase c;
  c.mount.sx_mm = 0.03;
  c.mount.dx_mm = 0.05;
  std::vector<Eigen::VectorXd> eps;
  std::vector<magenc::UnitAngles> psi;
  for (auto _ : state) {
    fast.eps(c, eps, &psi);
    benchmark::DoNotOptimize(eps[0].data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(FastCase, static, -1.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(FastCase, speed_no_hold, 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(FastCase, speed_hold, 10416.67)->Unit(benchmark::kMicrosecond);

// The Monte Carlo engine on a 32 mm ring (R 16, Ri 11, L 4 mm; ring:8 at r0 13.5 mm, 1 mm above the
// top face) and on the multipole study's 32-pole-pair axial code ring (R 15, Ri 11, L 1.5 mm, Br 0.3 T;
// ring:8 with electrical spacing at r0 13 mm, 0.4 mm above the top face; studies/multipole/multipole.toml)
// against the default magnet (ring:8 at r0 2.4 mm, z_s 4.55 mm), 360 theta nodes each: the surrogate's
// build (once per design) and one sample. The uniform magnets: CircleFieldModel `automatic` (symmetry-built
// on the exact field) and FastPipeline::eps. The multipole ring: MultipoleRingModel (reach 0.3 mm radial,
// 0.15 mm vertical) and MultipolePipeline::eps, the incremental reading (probe/multipole_pipeline.hpp).
// Counter fit_residual_uT: the surrogate's largest stencil misfit (the multipole model's misfit_T off its
// grid).
enum class McRing { default_magnet, ring32, multipole32 };
struct McLayout {
  magenc::Magnet magnet;
  double r0_mm, plane_z_mm;
};
McLayout mc_layout(McRing ring) {
  McLayout l{magenc::Magnet{}, 2.4, 4.55};
  if (ring == McRing::ring32) {
    l.magnet.radius_mm = 16.0;
    l.magnet.inner_radius_mm = 11.0;
    l.r0_mm = 13.5;
    l.plane_z_mm = 3.0;
  } else if (ring == McRing::multipole32) {
    l.magnet.pattern = magenc::MagnetPattern::AxialMultipole;
    l.magnet.pole_pairs = 32;
    l.magnet.radius_mm = 15.0;
    l.magnet.inner_radius_mm = 11.0;
    l.magnet.height_mm = 1.5;
    l.magnet.br_T = 0.3;
    l.r0_mm = 13.0;
    l.plane_z_mm = 0.75 + 0.4;
  }
  return l;
}
std::unique_ptr<magenc::FieldSource> mc_field(const McLayout& l) {
  if (l.magnet.is_uniform()) return std::make_unique<magenc::AnalyticField>(l.magnet);
  return std::make_unique<magenc::MultipoleField>(l.magnet);
}
magenc::CircleFieldModel mc_model(const magenc::FieldSource& f, const McLayout& l) {
  return {f, l.r0_mm, l.plane_z_mm, 360, 0.3, 0.3, 4, false, magenc::CircleFieldModel::construction_named("automatic")};
}
magenc::MultipoleRingModel mc_multipole_model(const magenc::FieldSource& f, const McLayout& l) {
  return {f, l.magnet.pole_pairs, l.r0_mm, l.plane_z_mm, 0.3, 0.15};
}
void McModelBuild(benchmark::State& state, McRing ring) {
  const McLayout l = mc_layout(ring);
  const auto f = mc_field(l);
  double residual_T = 0;
  for (auto _ : state) {
    if (l.magnet.is_multipole()) {
      const magenc::MultipoleRingModel model = mc_multipole_model(*f, l);
      residual_T = model.misfit_T();
      benchmark::DoNotOptimize(model.harmonics());
    } else {
      const magenc::CircleFieldModel model = mc_model(*f, l);
      residual_T = model.fit_residual_T();
      benchmark::DoNotOptimize(model.terms());
    }
  }
  state.counters["fit_residual_uT"] = residual_T * 1e6;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(McModelBuild, default_magnet, McRing::default_magnet)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(McModelBuild, ring32, McRing::ring32)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(McModelBuild, multipole32, McRing::multipole32)->Unit(benchmark::kMillisecond);
void McSample(benchmark::State& state, McRing ring) {
  const McLayout l = mc_layout(ring);
  const auto f = mc_field(l);
  magenc::ToleranceCase c;
  c.mount.sx_mm = 0.03;
  c.mount.dx_mm = 0.05;
  std::vector<Eigen::VectorXd> eps;
  if (l.magnet.is_multipole()) {
    // The probes at electrical spacing (angles / p, as sensor_setup_from_config sets them), read incrementally.
    magenc::ProbeArray array = magenc::ProbeArray::parse("ring:8");
    for (double& b : array.angle_deg) b /= l.magnet.pole_pairs;
    const magenc::MultipoleRingModel model = mc_multipole_model(*f, l);
    const magenc::MultipolePipeline engine({&model}, {array}, l.magnet.pole_pairs, 360);
    for (auto _ : state) {
      engine.eps(c.mount, eps);
      benchmark::DoNotOptimize(eps[0].data());
    }
  } else {
    const magenc::CircleFieldModel model = mc_model(*f, l);
    magenc::FastPipeline fast(model, {magenc::ProbeArray::parse("ring:8")}, l.magnet.height_mm);
    std::vector<magenc::UnitAngles> psi;
    for (auto _ : state) {
      fast.eps(c, eps, &psi);
      benchmark::DoNotOptimize(eps[0].data());
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(McSample, default_magnet, McRing::default_magnet)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(McSample, ring32, McRing::ring32)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(McSample, multipole32, McRing::multipole32)->Unit(benchmark::kMicrosecond);

// The one-spot principles on the same mount (point array: M field vectors per case against the
// two-probe array's 2M Bz values); plate: a 0.2 mm sensing area, 4 x 4 points per reading.
void MountingCasePrinciple(benchmark::State& state, magenc::SensorPrinciple p, double plate_mm) {
  const magenc::AnalyticField f{magenc::Magnet{}};
  magenc::ProbeSetup setup;
  setup.array = magenc::ProbeArray::parse("point");
  setup.principle = p;
  setup.area.plate_mm = plate_mm;
  setup.steps = 3600;
  magenc::Mount m;
  m.sx_mm = 0.03;
  m.dx_mm = 0.05;
  for (auto _ : state) benchmark::DoNotOptimize(magenc::error_spectrum(f, setup, m).c_deg[1]);
  state.SetItemsProcessed(state.iterations());  // items = mounting cases
}
BENCHMARK_CAPTURE(MountingCasePrinciple, inplane_point, magenc::SensorPrinciple::InPlane, 0.0)
    ->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCasePrinciple, amr_point, magenc::SensorPrinciple::Amr, 0.0)
    ->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCasePrinciple, inplane_plate4x4, magenc::SensorPrinciple::InPlane, 0.2)
    ->UseRealTime()->Unit(benchmark::kMillisecond);

// The new terms: tilted = false: elevation + signal chain (Bz path); true: also both tilts (n.B path).
void MountingCaseNew(benchmark::State& state, const char* array, bool tilted) {
  magenc::Magnet mag;
  mag.magnetization_elevation_deg = 2.0;
  const magenc::AnalyticField f{mag};
  magenc::ProbeSetup setup;
  setup.array = magenc::ProbeArray::parse(array);
  setup.steps = 3600;
  setup.chain.offset_cos_mT = 0.1;
  setup.chain.offset_sin_mT = -0.1;
  setup.chain.gain_mismatch = 0.005;
  setup.chain.phase_error_deg = 0.2;
  magenc::Mount m;
  m.sx_mm = 0.03;
  m.dx_mm = 0.05;
  if (tilted) {
    m.tilt_x_deg = 0.5;
    m.tilt_y_deg = 0.3;
    m.magnet_tilt_deg = 0.5;
    m.magnet_tilt_azimuth_deg = 30.0;
  }
  for (auto _ : state) benchmark::DoNotOptimize(magenc::error_spectrum(f, setup, m).c_deg[1]);
  state.SetItemsProcessed(state.iterations());  // items = mounting cases
}
BENCHMARK_CAPTURE(MountingCaseNew, chain_elev_two, "two", false)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCaseNew, chain_elev_ring8, "ring:8", false)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCaseNew, tilted_two, "two", true)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(MountingCaseNew, tilted_ring8, "ring:8", true)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
