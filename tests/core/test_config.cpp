#include <catch2/catch.hpp>

#include <functional>

#include "core/config.hpp"
#include "core/errors.hpp"

using namespace magenc;

TEST_CASE("defaults match physics.md", "[core][contract]") {
  Config c(common_keys());
  CHECK(c.real("magnet.radius_mm") == 2.0);
  CHECK(c.real("magnet.height_mm") == 4.0);
  CHECK(c.real("magnet.br_T") == 1.2);
  CHECK(c.real("magnet.mu_r") == 1.05);
  CHECK(c.real("sensor.plane_height_mm") == 2.55);
  CHECK(c.real("sensor.r0_mm") == 2.4);
  CHECK(c.str("sensor.array") == "two");
  CHECK(c.integer("sensor.steps") == 3600);
}

TEST_CASE("toml and --set override in order", "[core]") {
  Config c(common_keys());
  c.load_toml_string("[magnet]\nradius_mm = 3\n[sensor]\narray = \"diff4\"\n");
  CHECK(c.real("magnet.radius_mm") == 3.0);
  CHECK(c.str("sensor.array") == "diff4");
  c.set("magnet.radius_mm=2.5");
  CHECK(c.real("magnet.radius_mm") == 2.5);
  // Round trip through the echoed TOML.
  Config d(common_keys());
  d.load_toml_string(c.to_toml());
  CHECK(d.real("magnet.radius_mm") == 2.5);
  CHECK(d.str("sensor.array") == "diff4");
}

TEST_CASE("bad input is rejected with the key and range named", "[core][bad-input]") {
  Config c(common_keys());
  auto msg = [&](auto&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(msg([&] { c.set("magnet.radius_mm=-1"); }),
             Catch::Contains("magnet.radius_mm") && Catch::Contains("(0, 1000] mm"));
  CHECK_THAT(msg([&] { c.set("magnet.radius_mm=nan"); }), Catch::Contains("magnet.radius_mm"));
  CHECK_THAT(msg([&] { c.set("sensor.steps=8"); }), Catch::Contains("sensor.steps"));
  CHECK_THAT(msg([&] { c.set("sensor.bogus=1"); }), Catch::Contains("unknown configuration key"));
  CHECK_THAT(msg([&] { c.load_toml_string("[magnet\nradius_mm = 2"); }), Catch::Contains("malformed TOML"));
  CHECK_THAT(msg([&] { c.load_toml_string("[magnet]\nheight_mm = 0\n"); }),
             Catch::Contains("magnet.height_mm"));
  CHECK_THAT(msg([&] { c.load_toml_string("[magnet]\nradius = 2\n"); }),
             Catch::Contains("unknown configuration key 'magnet.radius'"));
  CHECK_THAT(msg([&] { c.set("magnet.br_T=abc"); }), Catch::Contains("magnet.br_T"));
  // Out-of-range numbers: strtod raises FE_OVERFLOW, which must stay an input error in Debug
  // builds (fp_trap.hpp), not a SIGFPE.
  CHECK_THAT(msg([&] { c.set("magnet.radius_mm=1e999"); }), Catch::Contains("magnet.radius_mm"));
  CHECK_THAT(msg([&] { c.load_toml_string("[magnet]\nradius_mm = 1e999\n"); }),
             Catch::Contains("malformed TOML") && Catch::Contains("1e999"));
}

// Issue 13: hostile TOML. A 50,000-level dotted table header overflowed the stack inside toml++
// (reached from Config::load_toml_string); sensor.steps = 1e300 was cast to long before the range
// check (undefined: float-cast-overflow; the message said -9223372036854775808).
TEST_CASE("hostile TOML: deep nesting, huge input and huge integers are input errors", "[core][bad-input]") {
  Config c(common_keys());
  auto msg = [&](const std::string& toml) {
    try {
      c.load_toml_string(toml, "hostile.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string header = "[a";
  for (int i = 0; i < 50000; ++i) header += ".a";
  CHECK_THAT(msg(header + "]\nx = 1\n"), Catch::Contains("hostile.toml") && Catch::Contains("nested deeper"));
  std::string key = "a";
  for (int i = 0; i < 50000; ++i) key += ".a";
  CHECK_THAT(msg(key + " = 1\n"), Catch::Contains("nested deeper"));
  CHECK_THAT(msg("x = {" + key + " = 1}\n"), Catch::Contains("nested deeper"));
  CHECK_THAT(msg("x = " + std::string(50000, '[') + std::string(50000, ']') + "\n"), Catch::Contains("nested deeper"));
  CHECK_THAT(msg("x = " + std::string(50000, '{') + "\n"), Catch::Contains("nested deeper"));
  CHECK_THAT(msg(std::string(2 << 20, '#')), Catch::Contains("bytes"));
  // Within the bounds: ordinary files, decimals and strings with dots are not mistaken for nesting.
  CHECK(msg("[magnet]\nradius_mm = 2.5 # a.b.c.d.e.f.g.h.i.j\n[sensor]\narray = \"a.b.c.d.e.f.g.h.i.j\"\n") ==
        "no error");
  CHECK(c.real("magnet.radius_mm") == 2.5);
  CHECK_THAT(msg("[sensor]\nsteps = 1e300\n"),
             Catch::Contains("sensor.steps = 1e+300 is out of range") && Catch::Contains("integer in [16, 10000000]"));
  CHECK_THAT(msg("[sensor]\nsteps = -1e300\n"), Catch::Contains("sensor.steps = -1e+300 is out of range"));
  CHECK(c.integer("sensor.steps") == 3600);
  CHECK_THAT(msg("[sensor]\nsteps = 9223372036854775807\n"), Catch::Contains("sensor.steps"));
}

namespace {
std::vector<KeySpec> list_keys() {
  return {real_list_key("convergence.h_mm", {0.8, 0.55}, 0, 100, "mm", "zone edge lengths", true),
          int_list_key("convergence.orders", {1, 2}, 1, 2, "element orders"),
          string_list_key("study.arrays", {"two", "diff4", "ring:8"}, {}, "probe arrays"),
          string_list_key("study.interps", {"cubic"}, {"nearest", "linear", "cubic"}, "interpolations"),
          string_list_key("provenance.dirs", {}, {}, "solved fields (may be empty)", 0)};
}
std::string error_of(Config& c, const std::function<void(Config&)>& f) {
  try {
    f(c);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST_CASE("list keys: TOML arrays and comma-separated text give the same typed elements", "[core][contract]") {
  Config c(list_keys());
  CHECK(c.reals("convergence.h_mm") == std::vector<double>{0.8, 0.55});
  CHECK(c.integers("convergence.orders") == std::vector<long>{1, 2});
  CHECK(c.strings("study.arrays") == std::vector<std::string>{"two", "diff4", "ring:8"});
  CHECK(c.strings("provenance.dirs").empty());
  // The comma text of a list key is what earlier configurations wrote and what config.toml echoes.
  CHECK(c.str("convergence.h_mm") == "0.8,0.55");
  CHECK(c.str("study.arrays") == "two,diff4,ring:8");
  c.load_toml_string("[convergence]\nh_mm = [0.4, 0.3, 0.2]\norders = [2]\n[study]\narrays = [\"diff4\", \"ring:6\"]\n");
  CHECK(c.reals("convergence.h_mm") == std::vector<double>{0.4, 0.3, 0.2});
  CHECK(c.integers("convergence.orders") == std::vector<long>{2});
  CHECK(c.strings("study.arrays") == std::vector<std::string>{"diff4", "ring:6"});
  c.load_toml_string("[convergence]\nh_mm = \"0.5, 0.25\"\norders = \"1,2\"\n[provenance]\ndirs = [\"a\"]\n");
  CHECK(c.reals("convergence.h_mm") == std::vector<double>{0.5, 0.25});
  CHECK(c.integers("convergence.orders") == std::vector<long>{1, 2});
  CHECK(c.strings("provenance.dirs") == std::vector<std::string>{"a"});
  c.set("study.arrays=two, diff4");
  CHECK(c.strings("study.arrays") == std::vector<std::string>{"two", "diff4"});
  c.set("convergence.h_mm=[0.1, 2]");
  CHECK(c.reals("convergence.h_mm") == std::vector<double>{0.1, 2.0});
  c.set("provenance.dirs=");
  CHECK(c.strings("provenance.dirs").empty());
  // Round trip through the echoed TOML.
  Config d(list_keys());
  d.load_toml_string(c.to_toml());
  CHECK(d.reals("convergence.h_mm") == c.reals("convergence.h_mm"));
  CHECK(d.strings("study.arrays") == c.strings("study.arrays"));
}

TEST_CASE("list keys: bad elements name the key the element and the allowed range", "[core][bad-input]") {
  Config c(list_keys());
  const std::string numbers = "an array of 1 or more numbers, each (0, 100] mm";
  auto toml = [](const std::string& text) { return [text](Config& x) { x.load_toml_string(text, "f.toml"); }; };
  auto set = [](const std::string& text) { return [text](Config& x) { x.set(text); }; };
  CHECK_THAT(error_of(c, toml("[convergence]\nh_mm = [0.4, nan]\n")),
             Catch::Contains("f.toml: convergence.h_mm element 2 of 2 = nan") && Catch::Contains(numbers));
  CHECK_THAT(error_of(c, toml("[convergence]\nh_mm = [0.4, \"0.3\"]\n")),
             Catch::Contains("convergence.h_mm element 2 of 2 = '0.3'") && Catch::Contains(numbers));
  CHECK_THAT(error_of(c, toml("[convergence]\nh_mm = []\n")),
             Catch::Contains("convergence.h_mm has 0 elements") && Catch::Contains(numbers));
  CHECK_THAT(error_of(c, toml("[convergence]\nh_mm = [[0.4]]\n")),
             Catch::Contains("convergence.h_mm element 1 of 1 is an array or table"));
  CHECK_THAT(error_of(c, toml("[convergence]\nh_mm = 0.4\n")), Catch::Contains("convergence.h_mm must be an array"));
  CHECK_THAT(error_of(c, toml("[convergence]\norders = [1, 3]\n")),
             Catch::Contains("convergence.orders element 2 of 2 = 3") && Catch::Contains("integer in [1, 2]"));
  CHECK_THAT(error_of(c, toml("[convergence]\norders = [1.5]\n")), Catch::Contains("convergence.orders element 1 of 1"));
  CHECK_THAT(error_of(c, toml("[study]\narrays = [\"two\", 4]\n")),
             Catch::Contains("study.arrays element 2 of 2 = 4") && Catch::Contains("non-empty strings"));
  CHECK_THAT(error_of(c, toml("[study]\narrays = [\"two\", \"\"]\n")), Catch::Contains("study.arrays element 2 of 2 is empty"));
  CHECK_THAT(error_of(c, toml("[study]\ninterps = [\"cubic\", \"spline\"]\n")),
             Catch::Contains("study.interps element 2 of 2 = 'spline'") && Catch::Contains("one of nearest, linear, cubic"));
  CHECK_THAT(error_of(c, set("convergence.h_mm=0.4,inf")), Catch::Contains("--set: convergence.h_mm element 2 of 2"));
  CHECK_THAT(error_of(c, set("convergence.h_mm=0.4,")), Catch::Contains("convergence.h_mm element 2 of 2"));
  CHECK_THAT(error_of(c, set("convergence.h_mm=[0.4, -1]")), Catch::Contains("convergence.h_mm element 2 of 2 = -1"));
  CHECK_THAT(error_of(c, set("convergence.h_mm=[0.4")), Catch::Contains("convergence.h_mm = '[0.4' is not a TOML array"));
  CHECK_THAT(error_of(c, set("study.arrays=")), Catch::Contains("study.arrays has 0 elements"));
  // A refused value leaves the previous one in place.
  CHECK(c.reals("convergence.h_mm") == std::vector<double>{0.8, 0.55});
  CHECK(c.strings("study.arrays") == std::vector<std::string>{"two", "diff4", "ring:8"});
}
