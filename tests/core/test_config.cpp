#include <catch2/catch.hpp>

#include "core/config.hpp"
#include "core/errors.hpp"

using namespace magenc;

TEST_CASE("defaults match physics.md", "[config]") {
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

TEST_CASE("toml and --set override in order", "[config]") {
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

TEST_CASE("bad input is rejected with the key and range named", "[config][bad-input]") {
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
TEST_CASE("hostile TOML: deep nesting, huge input and huge integers are input errors", "[config][bad-input]") {
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
