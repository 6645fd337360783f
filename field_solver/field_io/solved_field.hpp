// A solve_field output directory (docs/interfaces.md): DIR/solve.json (the record of
// the solve), DIR/mesh.vtu (the FE solution that fem:DIR sources evaluate),
// DIR/plane.vti and DIR/box.vti (the grids that grid: sources sample). The one
// reader of solve.json and the one place fem:DIR field sources are opened:
//   SolvedFieldDir          facts of the record, whether it is a solve of the
//                           configured magnet, the FE solution as a FieldSource
//   open_field_source       make_field_source (fields/field_factory) plus fem:DIR
// analysis/ builds on it (the [fem_field] sources of the FEM-vs-exact studies:
// fem_sources_from_config in analysis/fem_comparison.hpp).
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "field_solver/field_io/solve_facts.hpp"
#include "core/config.hpp"
#include "field_solver/field_io/fem_field.hpp"
#include "fields/field_factory.hpp"

namespace magenc {

class SolvedFieldDir {
 public:
  // Nothing is read here: each query reads what it needs, so a fem: source
  // (mesh.vtu only) opens even when solve.json is damaged.
  explicit SolvedFieldDir(std::filesystem::path dir) : dir_(std::move(dir)) {}
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path record_file() const { return dir_ / "solve.json"; }
  bool has_record() const;  // DIR/solve.json exists

  // Why the solve does not fit cfg's magnet and sensing plane (magnet.radius_mm,
  // height_mm, br_T, magnetization_elevation_deg, z_s differ from solve.json),
  // e.g. "was solved with magnet.radius_mm = 2, the study uses 3: ..."; "" when
  // it fits, or solve.json is absent or records no magnet. InputError when
  // solve.json is there but is not a JSON object or a checked value is no number.
  std::string mismatch(const Config& cfg) const;
  // InputError "<key>: 'DIR' <why>" when mismatch(cfg) is not empty, then
  // "<key>: 'DIR' has no F: run solve_field first (...)" for the first of
  // mesh.vtu, plane.vti, solve.json that is missing.
  void require_complete_solve_of(const Config& cfg, const std::string& key) const;

  // The facts of solve.json for summaries and tables; InputError naming the
  // file when it is missing or not a solve record (order 1..2, elements and
  // dofs required and integers in range).
  FeSolveFacts facts() const;
  // Selected facts for summaries ("order 2, 230k tetrahedra, ..."); "" when
  // solve.json is missing or unreadable (never throws).
  std::string description() const;
  // magnet.mu_r of solve.json, NaN when absent; InputError when not a number.
  double mu_r() const;

  // The FE solution of DIR/mesh.vtu, evaluated directly; InputError when
  // missing or malformed.
  std::shared_ptr<const FemField> fem() const;

 private:
  std::filesystem::path dir_;
};

// make_field_source (linear, analytic, grid:FILE.vti, table:FILE) plus
// fem:DIR = SolvedFieldDir(DIR).fem(); errors of fem:DIR are one InputError
// line starting "--field fem:DIR: ".
FieldSourcePtr open_field_source(const std::string& spec, const Config& cfg, const FieldOptions& opts = {});


}  // namespace magenc
