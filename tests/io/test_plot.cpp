// src/io/plot.cpp: gnuplot driver writes NAME.png (a real PNG), NAME.gp, NAME.dat;
// failures of gnuplot and bad inputs are reported, not ignored.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
#include "io/plot.hpp"
#include "support/study_test_util.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

using namespace magenc;
namespace fs = std::filesystem;

namespace {
// Pixels in the heat map palette's warm colours (red high, blue low) left of the colour box (the left
// 80 % of the picture): the drawn cells.
long warm_pixels(const fs::path& png) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(png.string().c_str());
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  const int nc = img->GetNumberOfScalarComponents();
  long n = 0;
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0] * 8 / 10; ++x) {
      const double r = img->GetScalarComponentAsDouble(x, y, 0, 0), b = img->GetScalarComponentAsDouble(x, y, 0, nc >= 3 ? 2 : 0);
      if (r > 150 && b < 170) ++n;
    }
  return n;
}

PlotSpec two_panel_spec() {
  PlotSeries sine{"sin {/Symbol q}", {}, {}, "lines", ""};
  PlotSeries pts{plot_literal("c3_deg (literal)"), {}, {}, "points", ""};
  for (int i = 0; i <= 36; ++i) {
    sine.x.push_back(10.0 * i);
    sine.y.push_back(std::sin(10.0 * i * M_PI / 180));
    pts.x.push_back(10.0 * i);
    pts.y.push_back(i == 5 ? NAN : 0.5 * std::cos(10.0 * i * M_PI / 180));
  }
  PlotPanel a{"first", "{/Symbol q} [deg]", "value [1]", {sine, pts}, false, false, {}};
  PlotPanel b{"empty series and log axis", "x [mm]", "y [deg]", {PlotSeries{"nothing", {}, {}, "lines", {}}}, false, false, {}};
  b.logy = true;
  return PlotSpec{"plot test", {a, b}, 2, 800, 400};
}
}  // namespace

TEST_CASE("write_plot writes a PNG with its script and data", "[io][contract]") {
  const fs::path dir = test::temp_out("plot");
  write_plot(dir, "demo", two_panel_spec());
  REQUIRE(fs::exists(dir / "demo.png"));
  CHECK(fs::file_size(dir / "demo.png") > 1000);
  std::ifstream png(dir / "demo.png", std::ios::binary);
  char sig[8] = {};
  png.read(sig, 8);
  CHECK(std::string(sig + 1, 3) == "PNG");
  CHECK(fs::exists(dir / "demo.gp"));
  CHECK(fs::exists(dir / "demo.dat"));
  const std::string gp = test::slurp(dir / "demo.gp");
  CHECK(gp.find("pngcairo") != std::string::npos);
  CHECK(gp.find("multiplot layout 1,2") != std::string::npos);
  CHECK(gp.find("c3\\_deg") != std::string::npos);  // plot_literal escaped the underscore
  CHECK_FALSE(fs::exists(dir / "demo.gnuplot.log"));
  fs::remove_all(dir);
}

TEST_CASE("write_plot reports gnuplot failures and bad input", "[io][bad-input]") {
  const fs::path dir = test::temp_out("plot_bad");
  PlotSpec bad = two_panel_spec();
  bad.panels[0].commands.push_back("set nonsense_option 42");
  CHECK_THROWS_AS(write_plot(dir, "bad", bad), ComputeError);
  CHECK_FALSE(fs::exists(dir / "bad.png"));

  PlotSpec mismatch = two_panel_spec();
  mismatch.panels[0].series[0].y.pop_back();
  CHECK_THROWS_AS(write_plot(dir, "mismatch", mismatch), InputError);
  CHECK_THROWS_AS(write_plot(dir, "a/b", two_panel_spec()), InputError);
  fs::remove_all(dir);
}

TEST_CASE("write_heatmap writes a labelled log-colour heat map and refuses inconsistent sizes", "[io][bad-input]") {
  const fs::path dir = test::temp_out("heatmap");
  HeatmapSpec h;
  h.title = "heat map test";
  h.column_labels = {"|a_0|", "c_1", "c_2"};
  h.row_labels = {"first", "second"};
  h.values = {{0.5, 0.0, 1e-6}, {NAN, 2.0, 0.01}};
  h.cell_text = {{"0.5", "0", "1e-6"}, {"", "2", "0.01"}};
  h.row_separators = {1};
  write_heatmap(dir, "hm", h);
  REQUIRE(fs::exists(dir / "hm.png"));
  CHECK(fs::file_size(dir / "hm.png") > 1000);
  // The cells are drawn (a blank NaN cell must not drop the whole image): the warm cells (2.0 and 0.5 on
  // a log scale from 1e-4) cover well over 1 % of the 1100 x 900 default picture.
  const long warm = warm_pixels(dir / "hm.png");
  INFO("warm pixels " << warm);
  CHECK(warm > 3000);
  std::ifstream dat(dir / "hm.dat");
  const std::string text((std::istreambuf_iterator<char>(dat)), {});
  CHECK(text.find("0 1 0.5 \"0.5\"") != std::string::npos);  // first row on top (y = 1)
  CHECK(text.find("1 1 0.0001 \"0\"") != std::string::npos);  // zero clipped to the log floor
  CHECK(text.find("0 0 NaN") != std::string::npos);          // a blank cell
  // Cell text is white on the dark end of the palette, black elsewhere.
  CHECK(text.find("1 0 2 \"2\" 16777215") != std::string::npos);
  CHECK(text.find("2 1 0.0001 \"1e-6\" 0\n") != std::string::npos);
  CHECK(text.find("0 0 NaN \"\" 0\n") != std::string::npos);
  HeatmapSpec bad = h;
  bad.values[1].pop_back();
  CHECK_THROWS_AS(write_heatmap(dir, "bad", bad), InputError);
  bad = h;
  bad.row_labels.pop_back();
  CHECK_THROWS_AS(write_heatmap(dir, "bad", bad), InputError);
  CHECK_FALSE(fs::exists(dir / "bad.png"));
  fs::remove_all(dir);
}
