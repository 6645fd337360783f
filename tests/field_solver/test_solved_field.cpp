// The solved field directory (field_solver/field_io/solved_field.hpp): the one reader of
// solve.json, its consistency check against the configured magnet, the fem: sources.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "analysis/fem_comparison.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "probe/common_keys.hpp"
#include "field_solver/field_io/solved_field.hpp"

using namespace magenc;

TEST_CASE("fem_sources_from_config: a missing solve directory is one line naming solve_field",
          "[field_solver][bad-input]") {
  std::vector<KeySpec> keys = common_keys();
  for (auto& k : fem_field_keys("plane.vti")) keys.push_back(k);
  keys.push_back(string_key("study.arrays", "two", {}, "arrays"));
  Config cfg(keys);
  cfg.set("fem_field.dir=/nonexistent/magenc_field");
  try {
    fem_sources_from_config(cfg);
    FAIL("no error for a missing fem_field.dir");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("solve_field") != std::string::npos);
    CHECK(what.find('\n') == std::string::npos);
  }
}

TEST_CASE("SolvedFieldDir::mismatch: a solve of another magnetization elevation is not this magnet", "[field_solver][bad-input]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("magenc_test_mismatch_elev_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Config cfg(common_keys());
  // An older solve.json without the key counts as elevation 0.
  std::ofstream(dir / "solve.json") << R"({"magnet": {"radius_mm": 2.0, "height_mm": 4.0, "br_T": 1.2}, "plane_z_mm": 4.55})";
  CHECK(SolvedFieldDir(dir).mismatch(cfg).empty());
  cfg.set("magnet.magnetization_elevation_deg=5");
  CHECK(SolvedFieldDir(dir).mismatch(cfg).find("magnetization_elevation_deg") != std::string::npos);
  std::ofstream(dir / "solve.json") << R"({"magnet": {"radius_mm": 2.0, "height_mm": 4.0, "br_T": 1.2, )"
                                    << R"("magnetization_elevation_deg": 5.0}, "plane_z_mm": 4.55})";
  CHECK(SolvedFieldDir(dir).mismatch(cfg).empty());
  fs::remove_all(dir);
}
