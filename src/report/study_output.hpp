// Common plumbing of the studies (studies/*.cpp), so each study stays thin:
//   run_study()   parses the common flags, builds the Config (defaults, then
//                 --config, then --set), opens the output directory as an
//                 AtomicDir (default output/<study>), runs the body, writes
//                 config.toml (the values used) and run.json (version, git
//                 revision, date, command line, wall time), then commits. A
//                 failure anywhere leaves no output directory behind.
//   StudyCase     the base setup, mount and field most studies start from.
//   md_*()        small builders for summary.md (numbers: core/format.hpp and
//                 fmt_deg below); dominant_harmonics()/harmonics_text() for
//                 the harmonic lists of summaries.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "analysis/sweep.hpp"
#include "core/atomic_output.hpp"
#include "core/config.hpp"
#include "core/format.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

class StudyOutput {
 public:
  // Opens <out> (or output/<study> when out is empty) as an AtomicDir.
  StudyOutput(std::string study, const std::string& out);
  const std::string& study() const { return study_; }
  // Where to write files now (temporary until commit()).
  const std::filesystem::path& dir() const { return dir_->path(); }
  // Where the files will be after commit().
  const std::filesystem::path& final_dir() const { return dir_->final_path(); }
  std::filesystem::path operator/(const std::string& file) const { return dir() / file; }
  // Writes dir()/file with the given text; ComputeError on I/O failure.
  void write_text(const std::string& file, const std::string& text) const;
  // Records the configuration used (config.toml) and the run facts (run.json).
  void write_run_info(const Config& cfg, const std::string& command_line, double wall_s) const;
  void commit() { dir_->commit(); }

 private:
  std::string study_;
  std::unique_ptr<AtomicDir> dir_;
};

// The case a study of one mounting starts from: the base probe setup ([sensor] keys, array two), the
// mount ([mount] keys) and the field source named by study.field, read in that order, so the first bad
// key is the one reported (InputError).
struct StudyCase {
  ProbeSetup base;
  Mount mount;
  FieldSourcePtr field;
  static StudyCase from_config(const Config& cfg);
};

// The body of a study: reads cfg, writes into out. Exceptions propagate.
using StudyBody = std::function<void(const Config& cfg, StudyOutput& out)>;

// main() of a study: `return run_study("linear_model", "help text", keys, argc, argv, body);`
// study_keys are the study's own keys, merged after common_keys(). Exit codes
// as run_main (0 ok, 2 input error, 3 compute error, 1 other).
int run_study(const std::string& study, const std::string& description,
              const std::vector<KeySpec>& study_keys, int argc, char** argv, const StudyBody& body);

// Angle-error values (deg) below this magnitude are rounding noise of the
// double-precision pipeline (an ideal mount on the exact field gives ~1e-14),
// shown as 0 in summaries and plots.
inline constexpr double kRoundingZeroDeg = 1e-12;
// An angle-error value (deg) in a summary table: fmt_auto(v, 4, kRoundingZeroDeg).
inline std::string fmt_deg(double v) { return fmt_auto(v, 4, kRoundingZeroDeg); }

// A Markdown table.
std::string md_table(const std::vector<std::string>& header,
                     const std::vector<std::vector<std::string>>& rows);
// A Markdown image line for a PNG in the study folder.
std::string md_image(const std::string& alt, const std::string& png_file);

// Harmonics n >= 1 of s whose amplitude c_n is at least max(floor_deg,
// rel * max_n c_n), largest first, at most max_count: e.g. "c1 3.376, c3 0.412".
// harmonics_text() gives "none" when nothing qualifies.
struct Harmonic {
  int n;         // harmonic order
  double c_deg;  // amplitude
};
std::vector<Harmonic> dominant_harmonics(const Spectrum& s, double floor_deg, double rel,
                                         int max_count);
// "c1 3.376, c3 0.412"; when h is empty: "none (largest cN = x)" from s, or
// "none (all c_n < 1e-12)" when every c_n is below kRoundingZeroDeg.
std::string harmonics_text(const std::vector<Harmonic>& h, int digits = 3);
std::string harmonics_text(const std::vector<Harmonic>& h, const Spectrum& s, int digits = 3);

}  // namespace magenc
