// Smoke test of the fem_convergence study on a tiny configuration: it runs,
// writes its files, and its numbers make sense (errors fall under refinement;
// the equal-area radius beats vertices-on-the-circle at 16 segments).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> head;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& s) {
    std::vector<std::string> v;
    std::stringstream ss(s);
    std::string c;
    while (std::getline(ss, c, ',')) v.push_back(c);
    return v;
  };
  if (std::getline(in, line)) head = split(line);
  while (std::getline(in, line)) {
    auto cells = split(line);
    std::map<std::string, std::string> r;
    for (size_t i = 0; i < head.size() && i < cells.size(); ++i) r[head[i]] = cells[i];
    rows.push_back(r);
  }
  return rows;
}
}  // namespace

TEST_CASE("fem_convergence study runs on a tiny configuration", "[fem][study]") {
  const fs::path out = fs::temp_directory_path() / ("magenc_fem_convergence_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cmd = std::string(MAGENC_BIN_DIR) +
                          "/fem_convergence --set convergence.h_zone_list=1.0,0.7 --set convergence.orders=1,2"
                          " --set convergence.faceting_segments=16 --set convergence.truncation_radii=20"
                          " --set convergence.side_h_zone_mm=0.8 --set grid.plane_step_mm=0.25"
                          " --set mesh.outer_radius_mm=30 --out " + out.string() + " 2> " + out.string() + ".log";
  REQUIRE(std::system(cmd.c_str()) == 0);
  for (const char* f : {"convergence.csv", "faceting.csv", "truncation.csv", "convergence.png", "summary.md", "potential.csv",
                        "shaft_potential.csv"})
    CHECK(fs::is_regular_file(out / f));
  // Total vs reduced potential at mu_r = 1.05 on the coarser mesh, against the
  // reduced solve of the finer one: the reduced error is far smaller (measured ~100x on coarse.toml).
  {
    auto pot = read_csv(out / "potential.csv");
    REQUIRE(pot.size() == 3);  // h 1.0: total, reduced; h 0.7: total
    CHECK(pot[0]["potential"] == "total");
    CHECK(pot[1]["potential"] == "reduced");
    const double tot = std::stod(pot[0]["rms_rel"]), red = std::stod(pot[1]["rms_rel"]);
    CAPTURE(tot, red);
    CHECK(red < tot / 5);
  }
  // Total vs split potential with a mu_r = 1000 shaft (magnet mu_r = 1), same layout: the split
  // carries only the shaft's reaction, so its error is far smaller (measured ~18x on coarse.toml).
  {
    auto pot = read_csv(out / "shaft_potential.csv");
    REQUIRE(pot.size() == 3);  // h 1.0: total, split; h 0.7: total
    CHECK(pot[0]["potential"] == "total");
    CHECK(pot[1]["potential"] == "split");
    const double tot = std::stod(pot[0]["rms_rel"]), split = std::stod(pot[1]["rms_rel"]);
    CAPTURE(tot, split);
    CHECK(split < tot / 3);
  }
  auto conv = read_csv(out / "convergence.csv");
  REQUIRE(conv.size() == 4);
  for (int o = 0; o < 2; ++o) {
    const double coarse = std::stod(conv[2 * o]["rms_rel"]), fine = std::stod(conv[2 * o + 1]["rms_rel"]);
    CAPTURE(o, coarse, fine);
    CHECK(fine < coarse);
  }
  CHECK(std::stod(conv[3]["rms_rel"]) < 0.01);  // P2 at 0.7 mm: measured ~0.5 %
  auto fac = read_csv(out / "faceting.csv");
  REQUIRE(fac.size() == 2);
  CHECK(fac[1]["equal_area"] == "true");
  // 16 segments: area deficit 2.6 %, which the equal-area radius removes.
  CHECK(std::stod(fac[1]["rms_rel"]) < 0.5 * std::stod(fac[0]["rms_rel"]));
  fs::remove_all(out);
}
