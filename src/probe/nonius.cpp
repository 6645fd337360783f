#include "probe/nonius.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/multipole_field.hpp"

namespace magenc {

std::vector<KeySpec> NoniusTrack::keys() {
  const double big = 1000;
  return {
      real_key("nonius.radius_mm", 0.0, 0, big, "mm", "outer radius of the nonius ring; 0 = no nonius track"),
      real_key("nonius.inner_radius_mm", 0.0, 0, big, "mm", "inner radius of the nonius ring"),
      real_key("nonius.height_mm", 1.5, 0, big, "mm", "height of the nonius ring", true),
      real_key("nonius.z_offset_mm", 0.0, -big, big, "mm", "centre of the nonius ring above the master's centre"),
      real_key("nonius.br_T", 0.3, 0, 10, "T", "remanence of the nonius ring", true),
      string_key("nonius.pattern", "axial_multipole", {"axial_multipole", "radial_multipole"},
                 "magnetization pattern of the nonius ring"),
      int_key("nonius.pole_pairs", 0, 0, 100000, "pole pairs of the nonius ring; 0 = the master's minus one"),
      string_key("nonius.array", "two", {}, "read head of the nonius track: two, diff4 or ring:N (electrical spacing)"),
      real_key("nonius.r0_mm", 0.0, 0, big, "mm", "read radius of the nonius head (over its track)"),
  };
}

bool NoniusTrack::present(const Config& cfg) { return cfg.has("nonius.radius_mm") && cfg.real("nonius.radius_mm") > 0; }

NoniusTrack NoniusTrack::from_config(const Config& cfg) {
  const Magnet master = Magnet::from_config(cfg);
  if (!master.is_multipole())
    throw InputError("nonius.radius_mm = " + num(cfg.real("nonius.radius_mm")) + " with magnet.pattern = " +
                     pattern_name(master.pattern) + ": a nonius needs a multipole master (axial_multipole, radial_multipole)");
  NoniusTrack t;
  t.magnet.radius_mm = cfg.real("nonius.radius_mm");
  t.magnet.inner_radius_mm = cfg.real("nonius.inner_radius_mm");
  t.magnet.height_mm = cfg.real("nonius.height_mm");
  t.magnet.br_T = cfg.real("nonius.br_T");
  t.magnet.pattern = cfg.str("nonius.pattern") == "radial_multipole" ? MagnetPattern::RadialMultipole
                                                                     : MagnetPattern::AxialMultipole;
  const long pn = cfg.integer("nonius.pole_pairs");
  t.magnet.pole_pairs = pn == 0 ? master.pole_pairs - 1 : static_cast<int>(pn);
  if (t.magnet.pole_pairs == master.pole_pairs || t.magnet.pole_pairs < 1)
    throw InputError("nonius.pole_pairs = " + std::to_string(t.magnet.pole_pairs) + " with magnet.pole_pairs = " +
                     std::to_string(master.pole_pairs) +
                     ": allowed pole pairs >= 1 and different from the master's (p - 1 for one period per turn)");
  t.magnet.validate();
  t.z_offset_mm = cfg.real("nonius.z_offset_mm");
  t.array = cfg.str("nonius.array");
  t.r0_mm = cfg.real("nonius.r0_mm");
  if (!(t.r0_mm >= t.magnet.inner_radius_mm && t.r0_mm <= t.magnet.radius_mm))
    throw InputError("nonius.r0_mm = " + num(t.r0_mm) + " is not over the nonius track (nonius.inner_radius_mm = " +
                     num(t.magnet.inner_radius_mm) + ", nonius.radius_mm = " + num(t.magnet.radius_mm) +
                     "): allowed inner_radius_mm <= r0_mm <= radius_mm");
  const bool radial_overlap = t.magnet.radius_mm > master.inner_radius_mm && t.magnet.inner_radius_mm < master.radius_mm;
  const bool z_overlap = std::abs(t.z_offset_mm) < 0.5 * (t.magnet.height_mm + master.height_mm);
  if (radial_overlap && z_overlap)
    throw InputError("nonius.radius_mm, nonius.inner_radius_mm, nonius.z_offset_mm: the nonius ring overlaps the "
                     "master ring's material: allowed rings apart in radius or in height");
  return t;
}

TrackSumField::TrackSumField(FieldSourcePtr master, FieldSourcePtr second, double second_z_offset_mm)
    : master_(std::move(master)), second_(std::move(second)), dz_(second_z_offset_mm) {}

Vec3 TrackSumField::B_T(const Vec3& p) const { return master_->B_T(p) + second_->B_T(Vec3(p - Vec3(0, 0, dz_))); }

double TrackSumField::Bz_T(const Vec3& p) const { return master_->Bz_T(p) + second_->Bz_T(Vec3(p - Vec3(0, 0, dz_))); }

FieldSourcePtr with_nonius(const FieldSourcePtr& master, const NoniusTrack& track) {
  return std::make_shared<TrackSumField>(master, std::make_shared<MultipoleField>(track.magnet), track.z_offset_mm);
}

ProbeSetup nonius_setup(const ProbeSetup& master, const NoniusTrack& track) {
  ProbeSetup s = master;
  s.array = ProbeArray::parse(track.array, "nonius.array");
  if (s.array.is_point()) throw InputError("nonius.array = 'point': allowed two, diff4, ring:N");
  for (double& b : s.array.angle_deg) b /= static_cast<double>(track.magnet.pole_pairs);
  s.r0_mm = track.r0_mm;
  s.pole_pairs = track.magnet.pole_pairs;
  s.multipole = true;
  return s;
}

NoniusResult nonius_decode(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& eps_master_deg,
                           const Eigen::VectorXd& eps_second_deg, int p, int p2) {
  NoniusResult r;
  const Eigen::Index M = eps_master_deg.size();
  r.eps_deg.resize(M);
  double worst = 0;
  for (Eigen::Index m = 0; m < M; ++m) {
    const double theta = theta_deg[m];
    // The electrical angles as read: phi_e = p (theta + eps) modulo 360 (the chip's orientation applied).
    const double pm = wrap_deg(p * (theta + eps_master_deg[m]));
    const double pn = wrap_deg(p2 * (theta + eps_second_deg[m]));
    const double D = wrap_deg(pm - pn);
    const double mm = std::round((p * D - pm) / 360.0);
    const double phi = (pm + 360.0 * mm) / p;
    r.eps_deg[m] = wrap_deg(phi - theta);
    const double d_star = theta + wrap_deg(D - theta);
    const double m_star = std::round((p * theta - pm) / 360.0);
    worst = std::max(worst, std::abs(p * d_star - pm - 360.0 * m_star));
    if (std::abs(r.eps_deg[m]) > 180.0 / p) ++r.slipped_samples;
  }
  r.margin_deg = 180.0 - worst;
  r.spectrum = spectrum_of(r.eps_deg);
  return r;
}

NoniusResult nonius_reading(const FieldSource& both, const ProbeSetup& master, const ProbeSetup& second,
                            const Mount& mount) {
  AngleErrorResult a = angle_error(both, master, mount);
  AngleErrorResult b = angle_error(both, second, mount);
  NoniusResult r = nonius_decode(a.theta_deg, a.eps_deg, b.eps_deg, master.pole_pairs, second.pole_pairs);
  r.master = std::move(a);
  r.second = std::move(b);
  return r;
}

}  // namespace magenc
