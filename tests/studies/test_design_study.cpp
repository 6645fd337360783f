// Study design end to end on a tiny space: exit 0 and the documented outputs; a target no design meets is a
// clear report (exit 0, "no design meets"); bad input is one line, exit 2, no output directory; under
// mpirun -n 2 the tables are byte-identical to one process.
#include <catch2/catch.hpp>

#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {

const std::string kTiny = "--config " + std::string(MAGENC_SOURCE_DIR) +
                          "/studies/design/design.toml --set design.samples=40 --set 'design.gap_mm=[1.5, 2.5]' "
                          "--set 'design.materials=[\"ndfeb_sintered\"]' --set 'design.br_T=[1.2]' "
                          "--set 'design.magnet_height_mm=[3]'";

std::string text_of(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("design study: a tiny run writes its outputs", "[studies][contract][cli]") {
  const fs::path out = temp_out("design_tiny");
  const StudyRun r = run_study_exe("design", out, kTiny);
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"design.csv", "design_pareto.csv", "design_budget.csv", "summary.md", "design_pareto.png",
                          "design_map.png", "run.json", "config.toml"});
  const std::string csv = text_of(out / "design.csv");
  // Header plus one row per design: 1 material x 3 radii x 1 height x 2 gaps x 2 r0 x 3 sensors.
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 36);
  CHECK(csv.rfind("index,material,br_T,magnet_radius_mm,magnet_height_mm,gap_mm,sensor,r0_mm,volume_mm3,", 0) == 0);
  const std::string md = text_of(out / "summary.md");
  CHECK((md.find("recommended design") != std::string::npos || md.find("no design meets") != std::string::npos));
  fs::remove_all(out);
}

TEST_CASE("design study: a target no design meets is reported, exit 0", "[studies][contract][cli]") {
  const fs::path out = temp_out("design_none");
  const StudyRun r = run_study_exe("design", out, kTiny + " --set design.target_p99_deg=1e-6");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string md = text_of(out / "summary.md");
  CHECK(md.find("no design meets the requirements") != std::string::npos);
  CHECK(md.find("Closest designs") != std::string::npos);
  CHECK(text_of(out / "design_budget.csv") == "index,group,p99_uncal_deg,p99_cal_deg\n");
  fs::remove_all(out);
}

TEST_CASE("design study: bad input is one line, exit 2, no output", "[studies][bad-input][cli]") {
  for (const std::string set : {"--set 'design.gap_mm=[]'", "--set 'design.sensors=[\"xmr\"]'",
                                "--set design.calibration=ogp", "--set design.temperature_max_C=-50"}) {
    CAPTURE(set);
    const fs::path out = temp_out("design_bad");
    const StudyRun r = run_study_exe("design", out, kTiny + " " + set);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find("design.") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(leftovers(out));
  }
}

#ifdef MAGENC_MPIEXEC
TEST_CASE("mpirun -n 2 design writes the tables of one process byte for byte", "[studies][mpi][determinism][cli]") {
  const fs::path one = temp_out("design_mpi1"), two = temp_out("design_mpi2"), plain = temp_out("design_mpi0");
  const std::string mpirun = std::string("timeout 300 ") + MAGENC_MPIEXEC + " --allow-run-as-root --oversubscribe ";
  auto run = [&](const std::string& prefix, const fs::path& out) {
    const std::string cmd = prefix + MAGENC_BIN_DIR + "/design --out '" + out.string() + "' " + kTiny +
                            " --set design.calibration=lut:32 > '" + out.string() + ".log' 2>&1";
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  };
  REQUIRE(run("", plain) == 0);
  REQUIRE(run(mpirun + "-n 1 ", one) == 0);
  REQUIRE(run(mpirun + "-n 2 ", two) == 0);
  for (const char* f : {"design.csv", "design_pareto.csv", "design_budget.csv"}) {
    INFO(f);
    const std::string a = text_of(plain / f);
    CHECK(a.size() > 50);
    CHECK(text_of(one / f) == a);
    CHECK(text_of(two / f) == a);
  }
  // Bad input under mpirun: rank 0 names it once, the other ranks exit alike, no output folder.
  const fs::path bad = temp_out("design_mpi_bad");
  const std::string cmd = mpirun + "-n 2 " + MAGENC_BIN_DIR + "/design --out '" + bad.string() + "' " + kTiny +
                          " --set 'design.gap_mm=[]' > '" + bad.string() + ".log' 2>&1";
  const int rc = std::system(cmd.c_str());
  CHECK((WIFEXITED(rc) && WEXITSTATUS(rc) != 0));
  const std::string log = text_of(bad.string() + ".log");
  std::size_t mentions = 0;
  for (std::size_t p = log.find("design.gap_mm"); p != std::string::npos; p = log.find("design.gap_mm", p + 1)) ++mentions;
  CHECK(mentions == 1);
  CHECK_FALSE(fs::exists(bad));
  fs::remove(bad.string() + ".log");
  // The summary names the rank count.
  CHECK(text_of(two / "summary.md").find("on 2 MPI ranks") != std::string::npos);
  for (const auto& p : {one, two, plain}) {
    fs::remove_all(p);
    fs::remove(p.string() + ".log");
  }
}
#endif
