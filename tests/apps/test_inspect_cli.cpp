// inspect executable (apps/inspect.cpp) end to end: a synthetic scan (exact field, known pose and
// polarization) written as CSV in mT, fitted by the executable; fit.json holds the truth within its sigma
// and the documented keys; bad input -> exit 2, one line, no output directory.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "analysis/inspect_fit.hpp"

namespace fs = std::filesystem;

namespace {
struct Run {
  int code;
  std::string err;
};
Run run_inspect(const fs::path& dir, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.string() + "' && '" MAGENC_BIN_DIR "/inspect' " + args + " > stdout.txt 2> stderr.txt";
  const int status = std::system(cmd.c_str());
  std::ifstream in(dir / "stderr.txt");
  std::stringstream ss;
  ss << in.rdbuf();
  fs::remove(dir / "stdout.txt");
  fs::remove(dir / "stderr.txt");
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
}
}  // namespace

TEST_CASE("inspect CLI: a synthetic noisy scan gives the truth within sigma in fit.json", "[apps][cli][contract]") {
  const fs::path dir = fs::temp_directory_path() / ("magenc_inspect_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  magenc::Magnet m;
  Eigen::Matrix3Xd p(3, 98);
  int j = 0;
  for (double z : {4.55, 5.55})
    for (int a = -3; a <= 3; ++a)
      for (int b = -3; b <= 3; ++b) p.col(j++) = Eigen::Vector3d(a, b, z);
  const magenc::InspectValues truth{0.05, -0.03, 0.08, 1.0, -0.5, 2.0, 1.17, 3.0, 2.0};
  Eigen::Matrix3Xd B = magenc::inspect_model_T(m, p, truth);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.05e-3);
  {
    std::ofstream out(dir / "scan.csv");
    out << "x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT\n";
    out.precision(12);
    for (int i = 0; i < p.cols(); ++i)
      out << p(0, i) << "," << p(1, i) << "," << p(2, i) << "," << 1e3 * (B(0, i) + noise(rng)) << ","
          << 1e3 * (B(1, i) + noise(rng)) << "," << 1e3 * (B(2, i) + noise(rng)) << "\n";
  }
  const Run r = run_inspect(dir, "--scan scan.csv --free offset,rotation,polarization,direction --out out");
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (const char* f : {"fit.json", "fit.csv", "summary.md", "components.png", "config.toml"})
    CHECK(fs::exists(dir / "out" / f));
  std::ifstream in(dir / "out" / "fit.json");
  const auto js = nlohmann::json::parse(in);
  const auto& table = magenc::inspect_parameters();
  for (int i = 0; i < magenc::kInspectParams; ++i) {
    const auto& e = js["parameters"][table[i].name];
    INFO(table[i].name << " " << e.dump());
    REQUIRE(e["sigma"].is_number());
    CHECK(e["free"].get<bool>());
    CHECK(std::abs(e["value"].get<double>() - truth[i]) < 4 * e["sigma"].get<double>());
  }
  CHECK(js["residual_rms_mT"].get<double>() == Approx(0.05).epsilon(0.2));

  // Bad input: one line, exit 2, no output directory.
  std::ofstream(dir / "bad.csv") << "x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT\n0,0,4.55,1,nan,3\n";
  for (const std::string& args : {std::string("--scan bad.csv --out bad"), std::string("--scan scan.csv --free tilt --out bad"),
                                  std::string("--scan missing.csv --out bad"),
                                  std::string("--scan scan.csv --set magnet.colour=1 --out bad")}) {
    const Run b = run_inspect(dir, args);
    INFO(args << ": " << b.err);
    CHECK(b.code == 2);
    CHECK(std::count(b.err.begin(), b.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(dir / "bad"));
  }
  fs::remove_all(dir);
}
