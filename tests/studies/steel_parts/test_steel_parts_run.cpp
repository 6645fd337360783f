// The study steel_parts' library half (studies/steel_parts/steel_parts_run.hpp): the parts it places
// around the magnet, and its inputs checked before any solve (one-line errors naming the key
// or file). The solves themselves are the FEM's (test_parts.cpp, test_nonlinear.cpp); the study
// runs in run.sh.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/cli.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "probe/common_keys.hpp"
#include "studies/steel_parts/steel_parts_run.hpp"

using namespace magenc;
using namespace magenc::fem;

namespace {

Config study_config(const std::vector<std::string>& sets) {
  CommonOptions o;
  o.config_file = std::string(MAGENC_SOURCE_DIR) + "/studies/steel_parts/steel_parts.toml";
  o.sets = sets;
  return load_config(merge_schemas(common_keys(), steel_parts_keys()), o);
}

std::string input_error(const std::vector<std::string>& sets) {
  try {
    run_steel_parts(study_config(sets), {MAGENC_SOURCE_DIR});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("steel_parts: the parts sit where the study says", "[studies][physics]") {
  const Config cfg = study_config({});
  const double R = cfg.real("magnet.radius_mm"), L = cfg.real("magnet.height_mm");
  const PartSpec cup = steel_parts_part("steel cup", cfg, "structural_steel");
  CHECK(cup.shape == PartShape::Cup);
  CHECK(cup.r_inner_mm == R);                 // the bore on the magnet's curved face
  CHECK(cup.z_min_mm + cup.base_mm == -0.5 * L);  // the base under the bottom face
  CHECK(cup.z_max_mm < 0.5 * L);
  const PartSpec shaft = steel_parts_part("steel shaft", cfg, "structural_steel");
  CHECK(shaft.z_max_mm == -0.5 * L);          // touching the bottom face
  const PartSpec shield = steel_parts_part("end shield", cfg, "structural_steel");
  CHECK(shield.z_max_mm < -0.5 * L);
  CHECK(shield.r_inner_mm > 0);
  CHECK(steel_parts_part("brass cup", cfg, "brass").r_outer_mm == cup.r_outer_mm);
}

TEST_CASE("steel_parts: bad inputs are one-line errors before any solve", "[studies][bad-input]") {
  const std::string parts = input_error({"parts=[{name = \"x\", shape = \"disk\", r_inner_mm = 4, r_outer_mm = 6, "
                                         "z_min_mm = -5, z_max_mm = -4, material = \"mu_r:10\"}]"});
  CHECK(parts.rfind("parts:", 0) == 0);
  const std::string file = input_error({"steel_parts.bh_file=no_such_curve.csv"});
  CAPTURE(file);
  CHECK(file.find("no_such_curve.csv") != std::string::npos);
  const std::string mat = input_error({"steel_parts.linear_material=unobtainium"});
  CAPTURE(mat);
  CHECK(mat.find("steel_parts.linear_material") != std::string::npos);
  const std::string bh = input_error({"steel_parts.linear_material=bh:materials/structural_steel_bh.csv"});
  CAPTURE(bh);
  CHECK(bh.find("steel_parts.bh_file") != std::string::npos);
  for (const auto& e : {parts, file, mat, bh}) CHECK(e.find('\n') == std::string::npos);
}
