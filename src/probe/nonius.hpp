// The nonius (Vernier) track of a multipole encoder (docs/physics.md "Multipole rings and nonius"): a
// second ring on the same rotor and mount, with its own pole pairs (default p - 1), its own Bz array with
// electrical spacing and read radius, its probes on the master's die plane and centre. Both rings' fields
// add at every probe (cross-talk included). The absolute angle:
//   D = wrap(phi_e,master - phi_e,nonius), m = round((p D - phi_e,master) / 360), phi = (phi_e,master + 360 m)/p,
//   eps = wrap(phi - theta) in (-180, 180] (a slip shows as a gross error of 360/p);
//   margin = 180 - max over the turn |p D* - phi_e,master - 360 m*| (master electrical degrees), D* = theta +
//   wrap(D - theta), m* = round((p theta - phi_e,master)/360); negative where the decoder slips.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "fields/magnet.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

struct NoniusTrack {
  Magnet magnet;              // its ring in its own frame (centred at z_offset_mm on the master's axis)
  double z_offset_mm = 0;     // centre height relative to the master's centre
  std::string array = "two";  // its read head (electrical spacing by its pole pairs)
  double r0_mm = 0;           // its read radius

  // The [nonius] keys; nullopt-like `present` false when nonius.radius_mm = 0 (no second track).
  static std::vector<KeySpec> keys();
  // Reads [nonius]; InputError (one line naming the keys) for: a nonius without a multipole master, equal
  // pole pairs, a read radius off its track, a ring that overlaps the master's material.
  static bool present(const Config& cfg);
  static NoniusTrack from_config(const Config& cfg);
};

// The field of several rings on one rotor: the sum of each source's field at p - (0, 0, z_offset).
class TrackSumField final : public FieldSource {
 public:
  TrackSumField(FieldSourcePtr master, FieldSourcePtr second, double second_z_offset_mm);
  std::string name() const override { return master_->name(); }
  Vec3 B_T(const Vec3& p_mm) const override;
  double Bz_T(const Vec3& p_mm) const override;
  using FieldSource::B_T;
  using FieldSource::Bz_T;
  const Magnet* exact_magnet() const override { return master_->exact_magnet(); }

 private:
  FieldSourcePtr master_, second_;
  double dz_;
};

struct NoniusResult {
  Eigen::VectorXd eps_deg;          // absolute error wrap(phi - theta), (-180, 180]
  double margin_deg = 0;            // synchronisation margin (master electrical degrees), < 0: slips
  int slipped_samples = 0;          // samples whose decoded period differs from the true one
  Spectrum spectrum;                // of eps_deg
  AngleErrorResult master, second;  // the two incremental readings
};

// The decoding above from the two incremental readings' errors (mechanical degrees) at theta_deg, the
// master's pole pairs p and the nonius's p2: eps_deg, margin_deg, slipped_samples and spectrum (master and
// second are left empty). The direct pipeline (nonius_reading) and the Monte Carlo engine share it.
NoniusResult nonius_decode(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& eps_master_deg,
                           const Eigen::VectorXd& eps_second_deg, int p, int p2);

// Both readings on `both` (TrackSumField), then the decoding above.
NoniusResult nonius_reading(const FieldSource& both, const ProbeSetup& master, const ProbeSetup& second,
                            const Mount& mount);

// The nonius read head: the master's setup (plane, centre, chain, steps) with the track's array, read radius
// and pole pairs (electrical spacing).
ProbeSetup nonius_setup(const ProbeSetup& master, const NoniusTrack& track);

// The nonius track's field source and the sum of both (the master's source first).
FieldSourcePtr with_nonius(const FieldSourcePtr& master, const NoniusTrack& track);

}  // namespace magenc
