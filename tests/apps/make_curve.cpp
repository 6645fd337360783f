// Test helper: writes a synthetic measured curve CSV (theta_deg,error_deg) of the forward model, with the
// reference-encoder noise and quantization of studies/diagnosis/diagnosis_study.hpp. For diagnose's CLI tests and
// worked examples:
//   magenc_make_curve OUT.csv [--field analytic|fem:DIR] [--array two] [--points 360] [--noise 0.005]
//                    [--quant 8192] [--zero 0.2] [--seed 1] [--turns 1] [--set key=value]...
// --set takes fit parameters by short name or key: --set sx=0.05 --set mount.dx_mm=0.02.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>

#include "analysis/sweep.hpp"
#include "studies/diagnosis/diagnosis_study.hpp"
#include "core/errors.hpp"
#include "probe/common_keys.hpp"
#include "field_solver/field_io/solved_field.hpp"
#include "fields/field_factory.hpp"
#include "report/study_output.hpp"

int main(int argc, char** argv) {
  return magenc::run_main("magenc_make_curve", [&] {
    CLI::App app{"synthetic measured curve"};
    std::string out, field = "analytic", array = "two";
    int points = 360, quant = 8192, turns = 1;
    unsigned seed = 1;
    double noise = 0.005, zero = 0.0;
    std::vector<std::string> sets;
    app.add_option("out", out)->required();
    app.add_option("--field", field);
    app.add_option("--array", array);
    app.add_option("--points", points);
    app.add_option("--noise", noise);
    app.add_option("--quant", quant);
    app.add_option("--zero", zero);
    app.add_option("--seed", seed);
    app.add_option("--turns", turns);
    app.add_option("--set", sets);
    CLI11_PARSE(app, argc, argv);
    magenc::Config cfg(magenc::common_keys());
    magenc::ModelState base{magenc::Mount{}, magenc::probe_setup_from_config(cfg, array)};
    std::vector<std::pair<std::string, double>> truth;
    for (const auto& s : sets) {
      const auto eq = s.find('=');
      truth.push_back({s.substr(0, eq), std::stod(s.substr(eq + 1))});
    }
    const auto f = magenc::open_field_source(field, cfg);
    std::mt19937 rng(seed);
    std::ofstream os(out);
    os << "theta_deg,error_deg\n";
    for (int t = 0; t < turns; ++t) {
      magenc::SyntheticOptions so;
      so.points = points;
      so.noise_deg = noise;
      so.quant_positions = quant;
      so.zero_deg = zero;
      const auto c = magenc::synthetic_curve(*f, base, magenc::table_values(base, truth), so, rng);
      char buf[96];
      for (Eigen::Index i = 0; i < c.curve.theta_deg.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.9f,%.9f\n", c.curve.theta_deg[i] + 360.0 * t, c.curve.error_deg[i]);
        os << buf;
      }
    }
    return 0;
  });
}
