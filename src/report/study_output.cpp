#include "report/study_output.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <omp.h>
#include <sstream>

#include "core/cli.hpp"
#include "core/errors.hpp"
#include "fields/field_factory.hpp"
#include "magenc_version.hpp"
#include "probe/common_keys.hpp"

namespace fs = std::filesystem;

namespace magenc {

StudyOutput::StudyOutput(std::string study, const std::string& out)
    : study_(std::move(study)),
      dir_(std::make_unique<AtomicDir>(out.empty() ? fs::path("output") / study_ : fs::path(out))) {}

void StudyOutput::write_text(const std::string& file, const std::string& text) const {
  std::ofstream f(dir() / file, std::ios::binary);
  f << text;
  f.flush();
  if (!f) throw ComputeError("writing " + (final_dir() / file).string() + " failed");
}

void StudyOutput::write_run_info(const Config& cfg, const std::string& command_line, double wall_s) const {
  write_text("config.toml", "# Configuration used by " + study_ + " (all keys, defaults included).\n" +
                                "# Re-run with: " + study_ + " --config config.toml\n\n" + cfg.to_toml());
  nlohmann::json j;
  j["study"] = study_;
  j["version"] = kVersion;
  j["git_revision"] = kGitRevision;
  j["date_utc"] = utc_timestamp_iso();
  j["command_line"] = command_line;
  j["wall_time_s"] = wall_s;
  j["threads"] = omp_get_max_threads();
  j["config"] = nlohmann::json::parse(cfg.to_json());
  write_text("run.json", j.dump(2) + "\n");
}

StudyCase StudyCase::from_config(const Config& cfg) {
  StudyCase c;
  c.base = probe_setup_from_config(cfg, "two");
  c.mount = Mount::from_config(cfg);
  c.field = make_field_source(cfg.str("study.field"), cfg);
  return c;
}

int run_study(const std::string& study, const std::string& description,
              const std::vector<KeySpec>& study_keys, int argc, char** argv, const StudyBody& body) {
  return run_main(study, [&]() -> int {
    const auto t0 = std::chrono::steady_clock::now();
    const auto schema = merge_schemas(common_keys(), study_keys);
    CLI::App app{description, study};
    CommonOptions opts;
    add_common_options(app, opts, schema);
    parse_cli(app, argc, argv);
    const Config cfg = load_config(schema, opts);

    // 1. Output folder (temporary until everything is written).
    StudyOutput out(study, opts.out);
    // 2. The study itself.
    body(cfg, out);
    // 3. Run facts, then commit.
    std::string cmd;
    for (int i = 0; i < argc; ++i) cmd += (i ? " " : "") + std::string(argv[i]);
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.write_run_info(cfg, cmd, wall_s);
    out.commit();
    std::cout << study << ": results in " << out.final_dir().string() << " (" << fmt(wall_s, 1)
              << " s)\n";
    return 0;
  });
}

std::string md_table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream os;
  os << "|";
  for (const auto& h : header) os << " " << h << " |";
  os << "\n|";
  for (std::size_t i = 0; i < header.size(); ++i) os << (i == 0 ? " --- |" : " ---: |");
  os << "\n";
  for (const auto& r : rows) {
    os << "|";
    for (const auto& c : r) os << " " << c << " |";
    os << "\n";
  }
  return os.str();
}

std::string md_image(const std::string& alt, const std::string& png_file) {
  return "![" + alt + "](" + png_file + ")\n";
}

std::vector<Harmonic> dominant_harmonics(const Spectrum& s, double floor_deg, double rel, int max_count) {
  double cmax = 0;
  for (int n = 1; n <= kHarmonics; ++n) cmax = std::max(cmax, s.c_deg[n]);
  const double thr = std::max(floor_deg, rel * cmax);
  std::vector<Harmonic> h;
  for (int n = 1; n <= kHarmonics; ++n)
    if (s.c_deg[n] >= thr) h.push_back({n, s.c_deg[n]});
  std::sort(h.begin(), h.end(), [](const Harmonic& a, const Harmonic& b) { return a.c_deg > b.c_deg; });
  if (static_cast<int>(h.size()) > max_count) h.resize(static_cast<std::size_t>(max_count));
  return h;
}

std::string harmonics_text(const std::vector<Harmonic>& h, int digits) {
  if (h.empty()) return "none";
  std::string t;
  for (const auto& x : h) t += (t.empty() ? "" : ", ") + ("c" + std::to_string(x.n) + " " + fmt(x.c_deg, digits));
  return t;
}

std::string harmonics_text(const std::vector<Harmonic>& h, const Spectrum& s, int digits) {
  if (!h.empty()) return harmonics_text(h, digits);
  int nmax = 1;
  for (int n = 2; n <= kHarmonics; ++n)
    if (s.c_deg[n] > s.c_deg[nmax]) nmax = n;
  if (s.c_deg[nmax] < kRoundingZeroDeg) return "none (all c_n < " + fmt_auto(kRoundingZeroDeg, 1) + ")";
  return "none (largest c" + std::to_string(nmax) + " = " + fmt_auto(s.c_deg[nmax], digits) + ")";
}

}  // namespace magenc
