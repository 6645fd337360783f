#include "analysis/provenance.hpp"

#include <cmath>
#include <map>
#include <sstream>

namespace magenc {

namespace {
std::string h_text(double h) {
  std::ostringstream os;
  os << h;
  return os.str();
}
}  // namespace

std::vector<ProvenanceRow> grid_sampling_scan(const FieldSource& exact, const ProbeSetup& setup,
                                              const std::vector<ProvenanceCase>& cases,
                                              const std::vector<double>& spacings_mm,
                                              const std::vector<Interp>& modes, double half_width_mm) {
  std::vector<Spectrum> exact_spectra;
  for (const auto& c : cases) exact_spectra.push_back(error_spectrum(exact, setup, c.mount));
  std::vector<ProvenanceRow> rows;
  for (const double h : spacings_mm) {
    const int half = static_cast<int>(std::ceil(half_width_mm / h - 1e-9));
    const int n = 2 * half + 1;
    const GridData g = sample_grid(exact, Vec3(-half * h, -half * h, setup.plane_z_mm), Vec3(h, h, h), {n, n, 1}, true);
    for (const Interp m : modes) {
      const GridField field(g, m);
      for (std::size_t i = 0; i < cases.size(); ++i) {
        ProvenanceRow r;
        r.source = "grid";
        r.variant = interp_name(m) + " h=" + h_text(h);
        r.h_mm = h;
        r.interp = interp_name(m);
        r.case_label = cases[i].label;
        r.exact = exact_spectra[i];
        r.sampled = error_spectrum(field, setup, cases[i].mount);
        rows.push_back(std::move(r));
      }
    }
  }
  return rows;
}

std::vector<ProvenanceRow> field_scan(const FieldSource& exact, const FieldSource& field, const std::string& source,
                                      const std::string& variant, const ProbeSetup& setup,
                                      const std::vector<ProvenanceCase>& cases) {
  std::vector<ProvenanceRow> rows;
  for (const auto& c : cases) {
    ProvenanceRow r;
    r.source = source;
    r.variant = variant;
    r.case_label = c.label;
    r.exact = error_spectrum(exact, setup, c.mount);
    r.sampled = error_spectrum(field, setup, c.mount);
    rows.push_back(std::move(r));
  }
  return rows;
}

std::vector<HarmonicVerdict> harmonic_verdicts(const std::vector<ProvenanceRow>& rows, double floor_deg) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ProvenanceRow*>> by_case;
  for (const auto& r : rows) {
    if (!by_case.count(r.case_label)) order.push_back(r.case_label);
    by_case[r.case_label].push_back(&r);
  }
  std::vector<HarmonicVerdict> out;
  for (const auto& label : order) {
    const auto& rs = by_case[label];
    for (int n = 1; n <= kHarmonics; ++n) {
      HarmonicVerdict v;
      v.case_label = label;
      v.n = n;
      v.exact_deg = rs.front()->exact.c_deg[n];
      v.physical = v.exact_deg >= floor_deg;
      v.best_artifact_deg = 1e300;
      for (const auto* r : rs) {
        const double a = std::abs(r->sampled.c_deg[n] - r->exact.c_deg[n]);
        if (a >= v.worst_artifact_deg) {
          v.worst_artifact_deg = a;
          v.worst_variant = r->variant;
        }
        if (a < v.best_artifact_deg) {
          v.best_artifact_deg = a;
          v.best_variant = r->variant;
        }
      }
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace magenc
