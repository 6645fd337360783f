#include <catch2/catch.hpp>

#include <functional>

#include "analysis/calibration.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "probe/common_keys.hpp"

using namespace magenc;

TEST_CASE("defaults match docs/physics.md", "[core][contract]") {
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

TEST_CASE("list keys: numbers() reads real and integer lists and the readers get elements not text", "[core][contract]") {
  Config c(list_keys());
  CHECK(c.numbers("convergence.h_mm") == std::vector<double>{0.8, 0.55});
  CHECK(c.numbers("convergence.orders") == std::vector<double>{1.0, 2.0});
  c.set("convergence.orders=[2]");
  CHECK(c.numbers("convergence.orders") == std::vector<double>{2.0});
  // Comma text is trimmed per element; a quoted element is the text inside the quotes.
  c.set("study.arrays= two ,  'ring:6' ");
  CHECK(c.strings("study.arrays") == std::vector<std::string>{"two", "ring:6"});
  // The typed accessors are for list keys of their type only (a programming error otherwise).
  CHECK_THROWS_AS(c.numbers("study.arrays"), std::logic_error);
  CHECK_THROWS_AS(c.strings("convergence.h_mm"), std::logic_error);
}

TEST_CASE("list keys: empty mixed nested non-finite and wrong-type elements and empty comma items are refused",
          "[core][bad-input]") {
  Config c(list_keys());
  const std::string numbers = "an array of 1 or more numbers, each (0, 100] mm";
  const std::string strings = "an array of 1 or more non-empty strings";
  auto toml = [](const std::string& text) { return [text](Config& x) { x.load_toml_string(text, "f.toml"); }; };
  auto set = [](const std::string& text) { return [text](Config& x) { x.set(text); }; };
  struct Case {
    std::function<void(Config&)> f;
    std::string says, range;
  };
  for (const auto& [f, says, range] : std::vector<Case>{
           {toml("[convergence]\nh_mm = []\n"), "convergence.h_mm has 0 elements", numbers},
           {set("convergence.h_mm=[]"), "--set: convergence.h_mm has 0 elements", numbers},
           {toml("[study]\narrays = []\n"), "study.arrays has 0 elements", strings},
           {toml("[convergence]\nh_mm = [0.4, \"a\"]\n"), "convergence.h_mm element 2 of 2 = 'a'", numbers},
           {toml("[study]\narrays = [\"two\", true]\n"), "study.arrays element 2 of 2 = true", strings},
           {set("convergence.h_mm=[0.4, true]"), "convergence.h_mm element 2 of 2 = true", numbers},
           {toml("[study]\narrays = [[\"two\"]]\n"), "study.arrays element 1 of 1 is an array or table", strings},
           {set("convergence.h_mm=[0.4, [0.3]]"), "convergence.h_mm element 2 of 2 is an array or table", numbers},
           {toml("[study]\narrays = [{ a = 1 }]\n"), "study.arrays element 1 of 1 is an array or table", strings},
           {toml("[convergence]\nh_mm = [inf]\n"), "convergence.h_mm element 1 of 1 = inf", numbers},
           {toml("[convergence]\nh_mm = [0.4, -nan]\n"), "convergence.h_mm element 2 of 2", numbers},
           {set("convergence.h_mm=0.4,1e999"), "convergence.h_mm element 2 of 2 = '1e999'", numbers},
           {toml("[convergence]\norders = [\"1\"]\n"), "convergence.orders element 1 of 1 = '1'", "integer in [1, 2]"},
           {toml("[convergence]\norders = [1e300]\n"), "convergence.orders element 1 of 1", "integer in [1, 2]"},
           {set("convergence.h_mm=0.4,,0.3"), "convergence.h_mm element 2 of 3 = ''", numbers},
           {set("study.arrays=two,,diff4"), "study.arrays element 2 of 3 is empty", strings},
           {set("study.arrays=two, "), "study.arrays element 2 of 2 is empty", strings},
           {toml("[study]\narrays = \"two,,diff4\"\n"), "f.toml: study.arrays element 2 of 3 is empty", strings},
       }) {
    const std::string e = error_of(c, f);
    INFO(e);
    CHECK_THAT(e, Catch::Contains(says) && Catch::Contains(range));
    CHECK(e.find('\n') == std::string::npos);
  }
  CHECK(c.reals("convergence.h_mm") == std::vector<double>{0.8, 0.55});
  CHECK(c.strings("study.arrays") == std::vector<std::string>{"two", "diff4", "ring:8"});
}

namespace {
// A table-list key like provenance.fem_variants: label (required), config, set (key = value).
std::vector<KeySpec> table_keys() {
  return {real_key("study.width_mm", 1, 0, 10, "mm", "a scalar beside the tables", true),
          table_list_key("study.variants",
                         {required(string_key("label", "", {}, "name")), string_key("config", "", {}, "file"),
                          int_key("repeat", 1, 1, 5, "repeats"), settings_field("set", "keys")},
                         "[{ label = \"a\", set = { fem.order = 1 } }]", "variants")};
}
}  // namespace

TEST_CASE("table-list keys: array-of-tables sections and --set inline arrays give the same tables", "[core][contract]") {
  Config c(table_keys());
  REQUIRE(c.tables("study.variants").size() == 1);  // the default
  c.load_toml_string("[study]\nwidth_mm = 2\n\n[[study.variants]]\nlabel = \"coarse P1\"\nconfig = \"meshes/coarse.toml\"\n"
                     "set = { fem.order = 1, \"mesh.h_zone_mm\" = 0.4, mesh = { symmetric = true }, fem.solver = \"petsc\" }\n\n"
                     "[[study.variants]]\nlabel = \"bare\"\nrepeat = 3\n");
  const ConfigTables t = c.tables("study.variants");
  REQUIRE(t.size() == 2);
  CHECK(t[0].text("label") == "coarse P1");
  CHECK(t[0].text("config") == "meshes/coarse.toml");
  const auto s = t[0].settings("set");
  REQUIRE(s.size() == 4);  // dotted, quoted-dotted and nested keys are all "section.key"
  CHECK(s[0].first == "fem.order");
  CHECK(std::get<long>(s[0].second) == 1);
  CHECK(s[1].first == "fem.solver");
  CHECK(std::get<std::string>(s[1].second) == "petsc");
  CHECK(s[2].first == "mesh.h_zone_mm");
  CHECK(std::get<double>(s[2].second) == 0.4);
  CHECK(s[3].first == "mesh.symmetric");
  CHECK(std::get<bool>(s[3].second));
  CHECK(t[1].text("label") == "bare");
  CHECK_FALSE(t[1].has("config"));
  CHECK(t[1].settings("set").empty());
  CHECK(c.real("study.width_mm") == 2.0);
  // The echoed TOML reads back to the same tables; the JSON is valid.
  Config d(table_keys());
  d.load_toml_string(c.to_toml());
  const ConfigTables u = d.tables("study.variants");
  REQUIRE(u.size() == 2);
  CHECK(u[0].settings("set") == s);
  CHECK(u[1].text("label") == "bare");
  CHECK(c.to_json().find("\"study.variants\": [{\"config\": \"meshes/coarse.toml\", \"label\": \"coarse P1\", "
                         "\"set\": {\"fem.order\": 1, \"fem.solver\": \"petsc\", \"mesh.h_zone_mm\": 0.4, "
                         "\"mesh.symmetric\": true}}, {\"label\": \"bare\", \"repeat\": 3}]") != std::string::npos);
  // --set: the same as an inline array; empty text or [] for none.
  c.set("study.variants=[{ label = \"x\", set = { fem.order = 2 } }]");
  REQUIRE(c.tables("study.variants").size() == 1);
  CHECK(c.tables("study.variants")[0].text("label") == "x");
  c.set("study.variants=[]");
  CHECK(c.tables("study.variants").empty());
  c.set("study.variants=");
  CHECK(c.tables("study.variants").empty());
  d.load_toml_string("[study]\nvariants = []\n");
  CHECK(d.tables("study.variants").empty());
}

TEST_CASE("table-list keys: bad tables are one line naming the key the element and the allowed fields",
          "[core][bad-input]") {
  Config c(table_keys());
  const std::string fields = "an array of tables {label = a non-empty string (required)";
  auto toml = [](const std::string& text) { return [text](Config& x) { x.load_toml_string(text, "f.toml"); }; };
  auto set = [](const std::string& text) { return [text](Config& x) { x.set(text); }; };
  struct Case {
    std::function<void(Config&)> f;
    std::string says;
  };
  for (const auto& [f, says] : std::vector<Case>{
           {toml("[[study.variants]]\nconfig = \"a.toml\"\n"), "f.toml: study.variants element 1 of 1: has no label"},
           {toml("[[study.variants]]\nlabel = \"a\"\n[[study.variants]]\nlabel = \"b\"\nbogus = 1\n"),
            "study.variants element 2 of 2: unknown field 'bogus'"},
           {toml("[[study.variants]]\nlabel = 1\n"), "study.variants element 1 of 1: field label must be a string"},
           {toml("[[study.variants]]\nlabel = \"\"\n"), "study.variants element 1 of 1: label is empty"},
           {toml("[[study.variants]]\nlabel = \"a\"\nrepeat = 9\n"), "field repeat = 9 is out of range"},
           {toml("[[study.variants]]\nlabel = \"a\"\nrepeat = 2.5\n"), "field repeat must be an integer"},
           {toml("[[study.variants]]\nlabel = \"a\"\nconfig = [\"x\"]\n"), "config is an array or table"},
           {toml("[[study.variants]]\nlabel = \"a\"\nset = \"fem.order=1\"\n"), "set is not a table of key = value"},
           {toml("[[study.variants]]\nlabel = \"a\"\nset = { fem.order = [1, 2] }\n"), "set key fem.order is an array"},
           {toml("[[study.variants]]\nlabel = \"a\"\nset = { fem.h = nan }\n"), "set key fem.h = nan is not finite"},
           {toml("[[study.variants]]\nlabel = \"a\"\nset = { fem.h = inf }\n"), "set key fem.h = inf is not finite"},
           {toml("[[study.variants]]\nlabel = \"a\"\nset = { \"fem.order\" = 1, fem = { order = 2 } }\n"),
            "set key fem.order is given twice"},
           {toml("[study]\nvariants = \"a: config=x fem.order=1\"\n"), "f.toml: study.variants must be an array of tables"},
           {toml("[study.variants]\nlabel = \"a\"\n"), "f.toml: study.variants must be an array of tables"},
           {toml("[study]\nvariants = [\"a\"]\n"), "study.variants element 1 of 1: is not a table"},
           {toml("[study]\nvariants = [[{ label = \"a\" }]]\n"), "study.variants element 1 of 1: is an array, not a table"},
           {set("study.variants=a: config=meshes/coarse.toml fem.order=1"),
            "--set: study.variants = 'a: config=meshes/coarse.toml fem.order=1' is not a TOML array of tables"},
           {set("study.variants=[{ label = \"a\""), "--set: study.variants is not a TOML array of tables"},
           {set("study.variants=[{ set = { fem.order = 1 } }]"), "--set: study.variants element 1 of 1: has no label"},
           {set("study.variants=[1, 2]"), "--set: study.variants element 1 of 2: is not a table"},
       }) {
    const std::string e = error_of(c, f);
    INFO(e);
    CHECK_THAT(e, Catch::Contains(says) && Catch::Contains(fields));
    CHECK(e.find('\n') == std::string::npos);
  }
  // A refused value leaves the previous one in place.
  REQUIRE(c.tables("study.variants").size() == 1);
  CHECK(c.tables("study.variants")[0].text("label") == "a");
}

namespace {
// A table-list key like parts: a name and a fixed-length number array offset_mm = [x, y].
std::vector<KeySpec> array_field_keys() {
  return {table_list_key("parts",
                         {required(string_key("name", "", {}, "name")),
                          real_array_field("offset_mm", 2, -1000, 1000, "mm", "xy of the axis")},
                         "", "parts")};
}
}  // namespace

TEST_CASE("table-list keys: a fixed-length number array field from a file, --set and the echo", "[core][contract]") {
  Config c(array_field_keys());
  CHECK(c.tables("parts").empty());
  c.load_toml_string("[[parts]]\nname = \"a\"\noffset_mm = [2.5, 0]\n\n[[parts]]\nname = \"b\"\n"
                     "\n[[parts]]\nname = \"c\"\noffset_mm = [-1000, 1e3]\n");
  ConfigTables t = c.tables("parts");
  REQUIRE(t.size() == 3);
  CHECK(t[0].numbers("offset_mm") == std::vector<double>{2.5, 0.0});
  CHECK_FALSE(t[1].has("offset_mm"));
  CHECK(t[1].numbers("offset_mm").empty());
  CHECK(t[2].numbers("offset_mm") == std::vector<double>{-1000.0, 1000.0});
  // Integer elements are held as reals (a Real key's elements).
  REQUIRE(t[0].entries.size() == 2);
  REQUIRE(t[0].entries[1].array);
  CHECK(std::holds_alternative<double>((*t[0].entries[1].array)[1]));
  // The echo reads back to the same tables; the JSON writes the pair as an array.
  Config d(array_field_keys());
  d.load_toml_string(c.to_toml());
  REQUIRE(d.tables("parts").size() == 3);
  CHECK(d.tables("parts")[0].numbers("offset_mm") == std::vector<double>{2.5, 0.0});
  CHECK(d.to_toml() == c.to_toml());
  CHECK(c.to_toml().find("offset_mm = [2.5, 0.0]") != std::string::npos);
  CHECK(c.to_json().find("{\"name\": \"a\", \"offset_mm\": [2.5, 0]}") != std::string::npos);
  // --set: the same inline array.
  c.set("parts=[{ name = \"s\", offset_mm = [0, -3.25] }]");
  REQUIRE(c.tables("parts").size() == 1);
  CHECK(c.tables("parts")[0].numbers("offset_mm") == std::vector<double>{0.0, -3.25});
  // The allowed form, as --help and docs/keys.md show it.
  const std::string form = "offset_mm = an array of 2 numbers, each [-1000, 1000] mm";
  CHECK(allowed_range(c.schema().front()).find(form) != std::string::npos);
  CHECK(c.describe().find(form) != std::string::npos);
  CHECK(allowed_range(c.schema().front().fields[1]) == "an array of 2 numbers, each [-1000, 1000] mm");
}

TEST_CASE("table-list keys: a bad number array field is one line naming the element, the field and its form",
          "[core][bad-input]") {
  Config c(array_field_keys());
  c.set("parts=[{ name = \"ok\", offset_mm = [1, 2] }]");
  const std::string form = "offset_mm = an array of 2 numbers, each [-1000, 1000] mm";
  auto toml = [](const std::string& value) {
    return [value](Config& x) { x.load_toml_string("[[parts]]\nname = \"a\"\noffset_mm = " + value + "\n", "f.toml"); };
  };
  auto set = [](const std::string& value) {
    return [value](Config& x) { x.set("parts=[{ name = \"a\" }, { name = \"b\", offset_mm = " + value + " }]"); };
  };
  struct Case {
    std::function<void(Config&)> f;
    std::string says;
  };
  for (const auto& [f, says] : std::vector<Case>{
           {toml("[1]"), "f.toml: parts element 1 of 1: field offset_mm has 1 element:"},
           {toml("[1, 2, 3]"), "parts element 1 of 1: field offset_mm has 3 elements"},
           {toml("[]"), "parts element 1 of 1: field offset_mm has 0 elements"},
           {toml("[\"1\", 2]"), "parts element 1 of 1: field offset_mm element 1 of 2 must be a number"},
           {toml("[true, 2]"), "field offset_mm element 1 of 2 must be a number"},
           {toml("[0, nan]"), "field offset_mm element 2 of 2 = nan is out of range"},
           {toml("[-inf, 0]"), "field offset_mm element 1 of 2 = -inf is out of range"},
           {toml("[0, 1000.5]"), "field offset_mm element 2 of 2 = 1000.5 is out of range"},
           {toml("[-1001, 0]"), "field offset_mm element 1 of 2 = -1001 is out of range"},
           {toml("[[1], 2]"), "field offset_mm element 1 of 2 is an array or table"},
           {toml("2.5"), "parts element 1 of 1: field offset_mm must be an array"},
           {toml("\"2.5,0\""), "field offset_mm must be an array"},
           {toml("{ x = 1, y = 2 }"), "field offset_mm must be an array"},
           {set("[1]"), "--set: parts element 2 of 2: field offset_mm has 1 element:"},
           {set("[1, 2, 3]"), "--set: parts element 2 of 2: field offset_mm has 3 elements"},
           {set("[1, \"x\"]"), "field offset_mm element 2 of 2 must be a number"},
           {set("[nan, 0]"), "field offset_mm element 1 of 2 = nan is out of range"},
           {set("[0, inf]"), "field offset_mm element 2 of 2 = inf is out of range"},
           {set("[2000, 0]"), "field offset_mm element 1 of 2 = 2000 is out of range"},
           {set("3"), "--set: parts element 2 of 2: field offset_mm must be an array"},
       }) {
    const std::string e = error_of(c, f);
    INFO(e);
    CHECK_THAT(e, Catch::Contains(says) && Catch::Contains(form));
    CHECK(e.find('\n') == std::string::npos);
  }
  // A refused value leaves the previous one in place.
  REQUIRE(c.tables("parts").size() == 1);
  CHECK(c.tables("parts")[0].numbers("offset_mm") == std::vector<double>{1.0, 2.0});
}

TEST_CASE("calibration.at is a table of keys from a file or --set or the default and is echoed and checked",
          "[core][contract][bad-input]") {
  Config cfg(merge_schemas(common_keys(), calibration_keys()));
  auto entries = [&] { return cfg.tables("calibration.at").front().settings("set"); };
  // The default of docs/interfaces.md.
  REQUIRE(entries().size() == 2);
  CHECK(entries()[0].first == "mount.dx_mm");
  CHECK(std::get<double>(entries()[0].second) == 0.1);
  // A file: inline table, or its own section with nested dotted keys.
  cfg.load_toml_string("[calibration]\nmethod = \"lut:32\"\nat = { mount.sx_mm = 0.05, sensor.gain_mismatch = 0.01 }\n");
  REQUIRE(entries().size() == 2);
  CHECK(entries()[0].first == "mount.sx_mm");
  CHECK(entries()[1].first == "sensor.gain_mismatch");
  cfg.load_toml_string("[calibration.at]\nmount.dz_mm = 0.2\n");
  REQUIRE(entries().size() == 1);
  CHECK(std::get<double>(entries()[0].second) == 0.2);
  // --set, and the echo reads back the same.
  cfg.set("calibration.at={ mount.dx_mm = 0.3, mount.sy_mm = -1 }");
  const std::string toml = cfg.to_toml();
  CHECK(toml.find("at = { mount.dx_mm = 0.3, mount.sy_mm = -1 }") != std::string::npos);
  CHECK(cfg.to_json().find("\"calibration.at\": {\"mount.dx_mm\": 0.3, \"mount.sy_mm\": -1}") != std::string::npos);
  Config back(merge_schemas(common_keys(), calibration_keys()));
  back.load_toml_string(toml);
  CHECK(back.to_toml() == toml);
  cfg.set("calibration.at={}");
  CHECK(entries().empty());
  for (const char* bad : {"calibration.at=5", "calibration.at={ a = [1, 2] }", "calibration.at={ a = ",
                          "calibration.at={ a = 1, a = 2 }", "calibration.at={ a = nan }"}) {
    CAPTURE(bad);
    try {
      cfg.set(bad);
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CHECK(msg.find("calibration.at") != std::string::npos);
      CHECK(msg.find('\n') == std::string::npos);
    }
  }
  CHECK_THROWS_AS(cfg.load_toml_string("[calibration]\nat = 3\n"), InputError);
  CHECK_THROWS_AS(cfg.load_toml_string("[calibration]\nat = [1]\n"), InputError);
}
