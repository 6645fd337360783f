// The Monte Carlo engine's multipole reading (src/probe/multipole_ring_model.hpp,
// src/probe/multipole_pipeline.hpp) against the direct pipeline on the exact sector field
// (probe/angle_error.hpp with the incremental reading), and docs/physics.md's multipole reference values
// through the engine.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "probe/multipole_pipeline.hpp"
#include "probe/multipole_ring_model.hpp"
#include "core/errors.hpp"
#include "fields/multipole_field.hpp"
#include "probe/angle_error.hpp"
#include "probe/nonius.hpp"
#include "probe/spectrum.hpp"

using namespace magenc;

namespace {

// The five offsets (sx, sy, dx, dy, dz) drawn from u, in that order.
Mount random_offsets(std::mt19937_64& rng, std::uniform_real_distribution<double>& u) {
  Mount mt;
  mt.sx_mm = u(rng);
  mt.sy_mm = u(rng);
  mt.dx_mm = u(rng);
  mt.dy_mm = u(rng);
  mt.dz_mm = u(rng);
  return mt;
}
Magnet small_ring(int p, MagnetPattern pattern = MagnetPattern::AxialMultipole) {
  Magnet m;
  m.pattern = pattern;
  m.pole_pairs = p;
  m.radius_mm = 5.0;
  m.inner_radius_mm = 3.0;
  m.height_mm = 1.0;
  m.br_T = 0.3;
  return m;
}

// The array with electrical spacing (angles / p), as sensor_setup_from_config sets it.
ProbeArray electrical(const std::string& spec, int p) {
  ProbeArray a = ProbeArray::parse(spec);
  for (double& b : a.angle_deg) b /= p;
  return a;
}

ProbeSetup direct_setup(const Magnet& m, const ProbeArray& a, double r0, double z, int steps) {
  ProbeSetup s;
  s.array = a;
  s.r0_mm = r0;
  s.plane_z_mm = z;
  s.steps = steps;
  s.magnet_height_mm = m.height_mm;
  s.pole_pairs = m.pole_pairs;
  s.multipole = true;
  return s;
}

// Largest |eps_engine - eps_direct| (deg) of every array over `mounts` random mounts within +-box mm.
double engine_vs_direct(const Magnet& m, int steps, int mounts, double box, unsigned seed, double* misfit_rel) {
  const MultipoleField field(m);
  const double r0 = 4.0, z = m.height_mm / 2 + 0.4;
  const MultipoleRingModel model(field, m.pole_pairs, r0, z, 0.3, 0.15);
  *misfit_rel = model.misfit_T() / model.amplitude_T();
  const std::vector<ProbeArray> arrays = {electrical("two", m.pole_pairs), electrical("diff4", m.pole_pairs),
                                          electrical("ring:6", m.pole_pairs)};
  const MultipolePipeline engine({&model}, arrays, m.pole_pairs, steps);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-box, box);
  double worst = 0;
  for (int i = 0; i < mounts; ++i) {
    const Mount mt = random_offsets(rng, u);
    std::vector<Eigen::VectorXd> eps;
    engine.eps(mt, eps);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      const AngleErrorResult d = angle_error(field, direct_setup(m, arrays[a], r0, z, steps), mt);
      REQUIRE(eps[a].size() == d.eps_deg.size());
      worst = std::max(worst, (eps[a] - d.eps_deg).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}
}  // namespace

TEST_CASE("multipole engine against the direct pipeline on small rings, p = 4..8", "[probe][cross-check]") {
  // The engine's error is the model's misfit (Chebyshev interpolation of the amplitudes, truncation) and the
  // skipped harmonics and envelope orders seen through the angle: |d eps| <~ misfit / |channel amplitude|
  // rad / p. Misfits of ~1e-7 of A_1 give ~1e-7 deg (measured: 3e-8 .. 2.1e-7 deg); the bound 5e-7 deg is
  // above that and ~1e6 below the errors compared (0.1-1 deg).
  for (const int p : {4, 6, 8}) {
    double misfit = 0;
    const double worst = engine_vs_direct(small_ring(p), 360, 3, 0.1, 100u + unsigned(p), &misfit);
    INFO("p = " << p << ": misfit " << misfit << " of A_1, largest eps difference " << worst << " deg");
    CHECK(misfit < 1e-6);
    CHECK(worst < 5e-7);
  }
  // A radial pattern, and N not a multiple of the probes' spacing (the engine needs no node on a probe).
  double misfit = 0;
  const double worst = engine_vs_direct(small_ring(6, MagnetPattern::RadialMultipole), 250, 2, 0.1, 7u, &misfit);
  INFO("radial p = 6, N = 250: misfit " << misfit << ", largest eps difference " << worst << " deg");
  CHECK(misfit < 1e-6);
  CHECK(worst < 5e-7);
}

TEST_CASE("multipole engine: the envelopes' order is enough", "[probe][convergence]") {
  const Magnet m = small_ring(8);
  const MultipoleField field(m);
  const MultipoleRingModel model(field, 8, 4.0, 0.9, 0.3, 0.15);
  MultipolePipeline engine({&model}, {electrical("two", 8)}, 8, 360);
  Mount mt;
  mt.dx_mm = 0.08;
  mt.dy_mm = -0.05;
  mt.sx_mm = 0.04;
  const int J = engine.envelope_order(mt);
  CHECK(J >= 2);
  std::vector<Eigen::VectorXd> auto_eps, more_eps, less_eps;
  engine.eps(mt, auto_eps);
  engine.force_envelope_order(J + 8);
  engine.eps(mt, more_eps);
  engine.force_envelope_order(1);
  engine.eps(mt, less_eps);
  INFO("J = " << J);
  // The orders left out are below 1e-8 of A_1 (kEnvelopeTol): an eps change of ~1e-8 rad / p = 7e-8 deg here.
  CHECK((auto_eps[0] - more_eps[0]).cwiseAbs().maxCoeff() < 7e-8);
  // (and the order matters: too few coarse angles are visibly wrong)
  CHECK((less_eps[0] - more_eps[0]).cwiseAbs().maxCoeff() > 1e-6);
}

TEST_CASE("multipole engine refuses tilts, probes off its reach and rings with pole errors", "[probe][bad-input]") {
  const Magnet m = small_ring(4);
  const MultipoleField field(m);
  const MultipoleRingModel model(field, 4, 4.0, 0.9, 0.3, 0.15);
  const MultipolePipeline engine({&model}, {electrical("two", 4)}, 4, 360);
  std::vector<Eigen::VectorXd> eps;
  Mount tilt;
  tilt.tilt_x_deg = 0.5;
  CHECK_THROWS_AS(engine.eps(tilt, eps), InputError);
  Mount far;
  far.sx_mm = 0.35;
  CHECK_THROWS_AS(engine.eps(far, eps), InputError);
  Mount high;
  high.dz_mm = 0.2;
  CHECK_THROWS_AS(engine.eps(high, eps), InputError);
  Magnet poles = m;
  poles.pole_edge_sigma_deg = 0.05;
  CHECK_THROWS_AS(MultipoleRingModel::check_ideal(poles), InputError);
  CHECK_THROWS_AS(MultipoleRingModel::check_ideal(Magnet{}), InputError);
  CHECK_NOTHROW(MultipoleRingModel::check_ideal(m));
  CHECK_THROWS_AS(MultipoleRingModel(field, 4, 4.0, 0.9, 0.0, 0.15), InputError);
}

TEST_CASE("multipole engine reproduces the 32-pole-pair reference values", "[probe][physics][regression]") {
  // docs/physics.md "Multipole rings and nonius": axial_multipole p = 32, Ri 11, R 15, L 1.5 mm, Br 0.3 T,
  // `two` at r0 13 mm, 0.4 mm above the top face, 360 steps.
  Magnet m;
  m.pattern = MagnetPattern::AxialMultipole;
  m.pole_pairs = 32;
  m.inner_radius_mm = 11.0;
  m.radius_mm = 15.0;
  m.height_mm = 1.5;
  m.br_T = 0.3;
  const MultipoleField field(m);
  const MultipoleRingModel model(field, 32, 13.0, 0.75 + 0.4, 0.3, 0.15);
  INFO("misfit " << model.misfit_T() << " T of A_1 " << model.amplitude_T() << " T, " << model.harmonics()
                 << " harmonics, Q " << model.quarter_samples() << ", " << model.field_evaluations() << " evaluations");
  CHECK(model.misfit_T() < 1e-6 * model.amplitude_T());
  const MultipolePipeline engine({&model}, {electrical("two", 32)}, 32, 360);
  std::vector<Eigen::VectorXd> eps;
  engine.eps(Mount{}, eps);
  Spectrum s = spectrum_of(eps[0], 32);
  CHECK(s.ce_deg[3] == Approx(0.09266).margin(5e-6));
  CHECK(s.pp_deg == Approx(0.18538).margin(5e-6));
  CHECK(s.c_deg[1] < 1e-9);
  CHECK(s.ce_deg[0] < 1e-9);
  Mount ecc;
  ecc.dx_mm = 0.05;
  engine.eps(ecc, eps);
  s = spectrum_of(eps[0], 32);
  CHECK(s.c_deg[1] == Approx(0.22030).margin(5e-6));
  CHECK(s.ce_deg[3] == Approx(0.08713).margin(5e-6));
  CHECK(s.pp_deg == Approx(0.62192).margin(5e-6));
}

TEST_CASE("multipole engine reads a nonius pair with cross-talk as the direct pipeline does", "[probe][cross-check]") {
  // A small (6, 5) pair: master ring R 5, Ri 3.5 read at r0 4.25; nonius ring R 3, Ri 1.5 at r0 2.25, 0.2 mm
  // lower; both fields at every probe. Engine: per head the models of both rings on its circle.
  Magnet master = small_ring(6);
  master.inner_radius_mm = 3.5;
  NoniusTrack track;
  track.magnet = small_ring(5);
  track.magnet.radius_mm = 3.0;
  track.magnet.inner_radius_mm = 1.5;
  track.z_offset_mm = -0.2;
  track.r0_mm = 2.25;
  const double z = master.height_mm / 2 + 0.4;
  const ProbeSetup head = direct_setup(master, electrical("two", 6), 4.25, z, 360);
  const ProbeSetup second = nonius_setup(head, track);
  const FieldSourcePtr both = with_nonius(std::make_shared<MultipoleField>(master), track);
  const MultipoleField fm(master), fn(track.magnet);
  const MultipoleRingModel mm(fm, 6, 4.25, z, 0.2, 0.12), nm(fn, 5, 4.25, z, 0.2, 0.12, 1e-9, -0.2);
  const MultipoleRingModel ns(fn, 5, 2.25, z, 0.2, 0.12, 1e-9, -0.2), ms(fm, 6, 2.25, z, 0.2, 0.12);
  const MultipolePipeline e_master({&mm, &nm}, {head.array}, 6, 360), e_second({&ns, &ms}, {second.array}, 5, 360);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.07, 0.07);
  for (int i = 0; i < 3; ++i) {
    const Mount mt = random_offsets(rng, u);
    const NoniusResult direct = nonius_reading(*both, head, second, mt);
    std::vector<Eigen::VectorXd> a, b;
    e_master.eps(mt, a);
    e_second.eps(mt, b);
    const NoniusResult engine = nonius_decode(direct.master.theta_deg, a[0], b[0], 6, 5);
    INFO("mount " << i << ": margin " << direct.margin_deg << " vs " << engine.margin_deg);
    // Each head within the single-ring bound (5e-7 deg); the margin's deviation is p (p - 1) = 30 times the
    // heads' mechanical errors, so 30 x 2 x 5e-7 deg.
    CHECK((a[0] - direct.master.eps_deg).cwiseAbs().maxCoeff() < 5e-7);
    CHECK((b[0] - direct.second.eps_deg).cwiseAbs().maxCoeff() < 5e-7);
    CHECK(engine.margin_deg == Approx(direct.margin_deg).margin(3e-5));
    CHECK(engine.slipped_samples == direct.slipped_samples);
    CHECK((engine.eps_deg - direct.eps_deg).cwiseAbs().maxCoeff() < 5e-7);
  }
}
