#include "multipole_engine.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "probe/multipole_pipeline.hpp"
#include "probe/multipole_ring_model.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/field_factory.hpp"
#include "fields/magnet.hpp"
#include "fields/multipole_field.hpp"
#include "probe/nonius.hpp"

namespace magenc {

std::vector<KeySpec> MultipoleStudyOptions::keys() {
  const MultipoleStudyOptions d;
  return merge_schemas(NoniusTrack::keys(), {
      int_key("study.steps", d.steps, 16, 100000, "theta samples per turn"),
      real_list_key("study.gaps_mm", {0.2, 0.4, 0.6, 0.8, 1.0}, -100, 100, "mm",
                    "read gaps above the top face of the interpolation part (sensor.plane_height_mm)"),
      string_list_key("study.arrays", {"two", "diff4"}, {}, "read heads of the interpolation part: two, diff4, ring:N"),
      real_list_key("study.eccentricities_mm", {0.01, 0.05, 0.1}, 0, 100, "mm",
                    "dynamic eccentricities (mount.dx_mm) of the e/r part"),
      int_key("study.pole_samples", d.pole_samples, 1, 1000000, "rings of the pole-error Monte Carlo (seeds 1..N)"),
      real_key("study.pole_edge_sigma_deg", d.pole_edge_sigma_deg, 0, 30, "deg",
               "pole-error Monte Carlo: sigma of each sector boundary (magnet.pole_edge_sigma_deg)"),
      real_key("study.pole_amplitude_sigma", d.pole_amplitude_sigma, 0, 0.3, "",
               "pole-error Monte Carlo: relative sigma of each sector's M0 (magnet.pole_amplitude_sigma)"),
      int_key("study.box_samples", d.box_samples, 1, 1000000, "mounts of the nonius tolerance box"),
      real_key("study.box_offset_mm", d.box_offset_mm, 0, 100, "mm", "tolerance box: sensor offsets sx, sy uniform in +-"),
      real_key("study.box_eccentricity_mm", d.box_eccentricity_mm, 0, 100, "mm",
               "tolerance box: magnet eccentricity dx, dy uniform in +-"),
      real_key("study.box_dz_mm", d.box_dz_mm, 0, 100, "mm", "tolerance box: air-gap change dz uniform in +-"),
      int_key("study.seed", d.seed, 0, 2147483647, "seed of the tolerance box"),
  });
}

MultipoleStudyOptions MultipoleStudyOptions::from_config(const Config& cfg) {
  const Magnet m = Magnet::from_config(cfg);
  if (!m.is_multipole())
    throw InputError("magnet.pattern = " + pattern_name(m.pattern) +
                     ": the multipole study reads a multipole ring: allowed axial_multipole, radial_multipole");
  MultipoleStudyOptions o;
  o.steps = static_cast<int>(cfg.integer("study.steps"));
  o.gaps_mm = cfg.reals("study.gaps_mm");
  o.arrays = cfg.strings("study.arrays");
  for (const std::string& a : o.arrays) {
    const ProbeArray pa = ProbeArray::parse(a, "study.arrays");
    if (pa.is_point()) throw InputError("study.arrays = 'point': allowed two, diff4, ring:N (Bz read heads)");
  }
  o.eccentricities_mm = cfg.reals("study.eccentricities_mm");
  o.pole_samples = static_cast<int>(cfg.integer("study.pole_samples"));
  o.pole_edge_sigma_deg = cfg.real("study.pole_edge_sigma_deg");
  o.pole_amplitude_sigma = cfg.real("study.pole_amplitude_sigma");
  o.box_samples = static_cast<int>(cfg.integer("study.box_samples"));
  o.box_offset_mm = cfg.real("study.box_offset_mm");
  o.box_eccentricity_mm = cfg.real("study.box_eccentricity_mm");
  o.box_dz_mm = cfg.real("study.box_dz_mm");
  o.seed = cfg.integer("study.seed");
  if (NoniusTrack::present(cfg)) NoniusTrack::from_config(cfg);  // its keys checked before any work
  // Every read head of the study, checked before any work (a read radius off the track, bad arrays).
  sensor_setup_from_config(cfg, cfg.str("sensor.array"));
  for (const std::string& a : o.arrays) sensor_setup_from_config(cfg, a, "study.arrays");
  return o;
}

namespace {

Config with_steps(const Config& cfg, int steps) {
  Config c = cfg;
  c.set("sensor.steps=" + std::to_string(steps));
  return c;
}

void interpolation_part(const Config& cfg, const MultipoleStudyOptions& opt, MultipoleStudyResult& r) {
  const FieldSourcePtr field = make_field_source("analytic", cfg);
  for (const double gap : opt.gaps_mm)
    for (const std::string& a : opt.arrays) {
      Config c = cfg;
      c.set_value("sensor.plane_height_mm", gap);
      const ProbeSetup s = sensor_setup_from_config(c, a, "study.arrays");
      const AngleErrorResult res = angle_error(*field, s, Mount{});
      r.interpolation.push_back({gap, a, electrical_harmonics_deg(res.eps_deg, s.pole_pairs), res.spectrum.pp_deg});
    }
}

void eccentricity_part(const Config& cfg, const MultipoleStudyOptions& opt, MultipoleStudyResult& r) {
  const FieldSourcePtr field = make_field_source("analytic", cfg);
  const ProbeSetup s = sensor_setup_from_config(cfg, cfg.str("sensor.array"));
  for (const double e : opt.eccentricities_mm) {
    Mount m;
    m.dx_mm = e;
    const AngleErrorResult res = angle_error(*field, s, m);
    r.eccentricity.push_back({e, res.spectrum.c_deg[1], rad_to_deg(e / s.r0_mm), res.spectrum.pp_deg});
  }
}

void pole_part(const Config& cfg, const MultipoleStudyOptions& opt, MultipoleStudyResult& r) {
  Config c = cfg;
  c.set_value("magnet.pole_edge_sigma_deg", opt.pole_edge_sigma_deg);
  c.set_value("magnet.pole_amplitude_sigma", opt.pole_amplitude_sigma);
  const ProbeSetup s = sensor_setup_from_config(c, c.str("sensor.array"));
  for (long seed = 1; seed <= opt.pole_samples; ++seed) {
    c.set_value("magnet.pole_seed", static_cast<long>(seed));
    const AngleErrorResult res = angle_error(*make_field_source("analytic", c), s, Mount{});
    r.poles.push_back({seed, res.spectrum.pp_deg, res.spectrum.c_deg[1], electrical_harmonics_deg(res.eps_deg, s.pole_pairs)});
  }
}

// A read head the Monte Carlo engine reads as the direct pipeline does: Bz points, no signal-chain error,
// the default orientation, neutral environment, static, on the axis.
bool plain_head(const ProbeSetup& s) {
  return s.principle == SensorPrinciple::Bz && s.chain.applied().ideal && s.orientation.identity() && s.area.point() &&
         s.env.neutral() && !s.speed.acts() && s.center_mm.isZero();
}

// The box's mounts through the Monte Carlo engine (probe/multipole_pipeline.hpp): per read head, the
// models of both rings on its circle (the other ring's field is the cross-talk), reach from the box.
struct NoniusEngine {
  std::vector<std::unique_ptr<MultipoleRingModel>> models;
  std::unique_ptr<MultipolePipeline> master, second;
  double misfit_T = 0;
};

NoniusEngine nonius_engine(const Magnet& mag, const NoniusTrack& track, const ProbeSetup& master,
                           const ProbeSetup& second, const MultipoleStudyOptions& opt) {
  NoniusEngine e;
  const MultipoleField fm(mag), fn(track.magnet);
  const double reach_rho = std::sqrt(2.0) * (opt.box_offset_mm + opt.box_eccentricity_mm) + 0.02;
  const double reach_z = opt.box_dz_mm + 0.02;
  auto model = [&](const MultipoleField& f, int p, const ProbeSetup& head, double z_off) {
    e.models.push_back(std::make_unique<MultipoleRingModel>(f, p, head.r0_mm, head.plane_z_mm, reach_rho, reach_z,
                                                            1e-9, z_off));
    e.misfit_T = std::max(e.misfit_T, e.models.back()->misfit_T());
    return e.models.back().get();
  };
  const int p = mag.pole_pairs, p2 = track.magnet.pole_pairs;
  const MultipoleRingModel* mm = model(fm, p, master, 0.0);
  const MultipoleRingModel* nm = model(fn, p2, master, track.z_offset_mm);
  e.master = std::make_unique<MultipolePipeline>(std::vector<const MultipoleRingModel*>{mm, nm},
                                                 std::vector<ProbeArray>{master.array}, p, master.steps);
  const MultipoleRingModel* ns = model(fn, p2, second, track.z_offset_mm);
  const MultipoleRingModel* ms = model(fm, p, second, 0.0);
  e.second = std::make_unique<MultipolePipeline>(std::vector<const MultipoleRingModel*>{ns, ms},
                                                 std::vector<ProbeArray>{second.array}, p2, second.steps);
  return e;
}

void nonius_part(const Config& cfg, const MultipoleStudyOptions& opt, MultipoleStudyResult& r) {
  const NoniusTrack track = NoniusTrack::from_config(cfg);
  const FieldSourcePtr both = with_nonius(make_field_source("analytic", cfg), track);
  const ProbeSetup master = sensor_setup_from_config(cfg, cfg.str("sensor.array"));
  const ProbeSetup second = nonius_setup(master, track);
  r.nonius_pole_pairs = track.magnet.pole_pairs;
  r.nonius_r0_mm = track.r0_mm;
  const NoniusResult ideal = nonius_reading(*both, master, second, Mount{});
  r.ideal_margin_deg = ideal.margin_deg;
  r.ideal_pp_deg = ideal.spectrum.pp_deg;
  // The box's mounts: the Monte Carlo engine where it reads the heads as the direct pipeline does (ideal
  // rings, plain heads), else the exact field at every mount.
  const Magnet mag = Magnet::from_config(cfg);
  const bool engine = mag.is_multipole() && mag.pole_edge_sigma_deg == 0.0 && mag.pole_amplitude_sigma == 0.0 &&
                      plain_head(master) && plain_head(second);
  NoniusEngine e;
  if (engine) e = nonius_engine(mag, track, master, second, opt);
  r.box_engine = engine;
  r.box_engine_misfit_T = e.misfit_T;
  const Eigen::VectorXd theta = uniform_theta_deg(master.steps);
  std::mt19937_64 rng(static_cast<std::uint64_t>(opt.seed));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> em, en;
  for (int i = 0; i < opt.box_samples; ++i) {
    Mount m;
    m.sx_mm = opt.box_offset_mm * u(rng);
    m.sy_mm = opt.box_offset_mm * u(rng);
    m.dx_mm = opt.box_eccentricity_mm * u(rng);
    m.dy_mm = opt.box_eccentricity_mm * u(rng);
    m.dz_mm = opt.box_dz_mm * u(rng);
    NoniusResult n;
    if (engine) {
      e.master->eps(m, em);
      e.second->eps(m, en);
      n = nonius_decode(theta, em[0], en[0], master.pole_pairs, second.pole_pairs);
    } else {
      n = nonius_reading(*both, master, second, m);
    }
    r.box.push_back({i + 1, m, n.margin_deg, n.spectrum.pp_deg, n.eps_deg.cwiseAbs().maxCoeff(), n.slipped_samples});
  }
}

}  // namespace

MultipoleStudyResult run_multipole_study(const Config& cfg_in, const MultipoleStudyOptions& opt) {
  const Config cfg = with_steps(cfg_in, opt.steps);
  MultipoleStudyResult r;
  r.options = opt;
  const Magnet m = Magnet::from_config(cfg);
  r.array = cfg.str("sensor.array");
  r.pole_pairs = m.pole_pairs;
  r.r0_mm = cfg.real("sensor.r0_mm");
  r.gap_mm = cfg.real("sensor.plane_height_mm");
  r.pole_pitch_mm = kPi * r.r0_mm / m.pole_pairs;
  interpolation_part(cfg, opt, r);
  eccentricity_part(cfg, opt, r);
  pole_part(cfg, opt, r);
  if (NoniusTrack::present(cfg)) nonius_part(cfg, opt, r);
  return r;
}

}  // namespace magenc
