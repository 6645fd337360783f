// Every input the fuzzers found (tests/fuzz/regressions/<target>_*) is read again by its reader, each in
// a forked child whose address space is capped at what it uses now + 1.5 GiB: the reader must refuse it
// with one InputError line naming the file. An input that makes a reader allocate what a header claims
// (gigabytes from a few hundred bytes) dies of std::bad_alloc in the child instead, and the test fails.
// (Under AddressSanitizer the cap is left off: its shadow memory already exceeds any such limit; the
// fuzz build's -malloc_limit_mb catches those allocations there.)
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>

#include <cstdio>
#include <new>

#include "analysis/measured_curve.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "fields/field_table.hpp"
#include "fields/grid_field.hpp"
#include "probe/common_keys.hpp"
#include "reliability/run_process.hpp"
#include "field_solver/field_io/solved_field.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define MAGENC_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MAGENC_ASAN 1
#endif
#endif

using namespace magenc_test;

namespace {

// Runs read(file) in a child; returns its exit code (0: InputError of one line naming the file,
// 1: accepted, 2: another exception, 3: a multi-line or anonymous InputError; -signal: crashed) and
// the message.
template <class F>
std::pair<int, std::string> refused_in_child(const fs::path& file, F read) {
  int fd[2];
  REQUIRE(::pipe(fd) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::close(fd[0]);
#ifndef MAGENC_ASAN
    long pages = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(f, "%ld", &pages) != 1) pages = 0;
      std::fclose(f);
    }
    const rlim_t cap = rlim_t(pages) * rlim_t(::sysconf(_SC_PAGESIZE)) + (rlim_t(3) << 29);
    const rlimit lim{cap, cap};
    ::setrlimit(RLIMIT_AS, &lim);
#endif
    int code = 1;
    std::string msg = "accepted";
    try {
      read(file);
    } catch (const magenc::InputError& e) {
      msg = e.what();
      code = msg.find('\n') == std::string::npos && msg.find(file.filename().string()) != std::string::npos ? 0 : 3;
    } catch (const std::bad_alloc&) {
      code = 2;
      msg = "std::bad_alloc";
    } catch (const std::exception& e) {
      code = 2;
      msg = e.what();
    }
    (void)!::write(fd[1], msg.data(), msg.size());
    ::_exit(code);
  }
  ::close(fd[1]);
  std::string msg;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd[0], buf, sizeof buf)) > 0;) msg.append(buf, std::size_t(n));
  ::close(fd[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status), msg};
}

}  // namespace

TEST_CASE("fuzz regressions: every found input is refused with one line and without the memory it claims",
          "[fields][regression][bad-input]") {
  const fs::path dir = fs::path(MAGENC_SOURCE_DIR) / "tests/fuzz/regressions";
  static const magenc::Config cfg(magenc::common_keys());
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    std::pair<int, std::string> r;
    if (name.rfind("vti_", 0) == 0)
      r = refused_in_child(e.path(), [](const fs::path& f) { (void)magenc::GridField::from_file(f, magenc::Interp::Linear); });
    else if (name.rfind("field_table_", 0) == 0)
      r = refused_in_child(e.path(), [](const fs::path& f) {
        (void)magenc::table_field_from_file(f, cfg, magenc::Interp::Cubic);
      });
    else if (name.rfind("measured_curve_", 0) == 0)
      r = refused_in_child(e.path(), [](const fs::path& f) { (void)magenc::read_measured_curve(f.string()); });
    else if (name.rfind("solve_json_", 0) == 0)
      r = refused_in_child(e.path(), [](const fs::path& f) {
        // A solve_field directory whose solve.json is this input: the summaries' description (documented
        // "" when unreadable, never throws) must not crash, then facts() refuses it naming solve.json.
        const fs::path d = fs::temp_directory_path() / ("magenc_fuzz_reg_" + std::to_string(::getpid()));
        fs::create_directories(d);
        fs::copy_file(f, d / "solve.json", fs::copy_options::overwrite_existing);
        const magenc::SolvedFieldDir solved(d);
        (void)solved.description();
        try {
          (void)solved.facts();
        } catch (const magenc::InputError& err) {
          // The child reports a refusal naming the input: map "DIR/solve.json" to this file's name.
          fs::remove_all(d);
          throw magenc::InputError(f.filename().string() + ": " + err.what());
        }
        fs::remove_all(d);
      });
    else
      FAIL("tests/fuzz/regressions/" << name << ": no reader for this prefix (vti_, field_table_, measured_curve_, "
                                               "solve_json_)");
    ++files;
    INFO(name << ": " << r.second);
    CHECK(r.first == 0);
  }
  WARN(files << " fuzz regression inputs refused");
  CHECK(files >= 7);
}

// The other side of the .vti pre-checks: every appended layout VTK writes (zlib or none, raw or base64,
// UInt32 or UInt64 headers, several compression blocks) and ascii are read back value for value.
TEST_CASE("the .vti pre-checks accept every appended data layout VTK writes", "[fields][contract]") {
  ScratchDir s("magenc_vti_layouts");
  vtkNew<vtkImageData> img;
  img->SetDimensions(5, 5, 1);
  img->SetOrigin(-2, -2, 4.55);
  img->SetSpacing(1, 1, 1);
  vtkNew<vtkDoubleArray> bz, b;
  bz->SetName("Bz");
  bz->SetNumberOfTuples(25);
  b->SetName("B");
  b->SetNumberOfComponents(3);
  b->SetNumberOfTuples(25);
  for (int i = 0; i < 25; ++i) {
    bz->SetValue(i, 0.01 * i);
    b->SetTuple3(i, 0.001 * i, -0.002 * i, 0.01 * i);
  }
  img->GetPointData()->AddArray(bz);
  img->GetPointData()->AddArray(b);
  int layouts = 0;
  for (int mode = 0; mode < 9; ++mode) {
    vtkNew<vtkXMLImageDataWriter> w;
    w->SetInputData(img);
    std::string name = "ascii.vti";
    if (mode == 8) {
      w->SetDataModeToAscii();
    } else {
      const bool zlib = mode & 1, base64 = mode & 2, u64 = mode & 4;
      w->SetDataModeToAppended();
      w->SetEncodeAppendedData(base64);
      if (zlib) w->SetCompressorTypeToZLib();
      else w->SetCompressorTypeToNone();
      if (u64) w->SetHeaderTypeToUInt64();
      else w->SetHeaderTypeToUInt32();
      w->SetBlockSize(64);  // B's 600 bytes in 10 blocks
      name = std::string(zlib ? "zlib" : "none") + (base64 ? "_base64" : "_raw") + (u64 ? "_u64" : "_u32") + ".vti";
    }
    const fs::path f = s.dir / name;
    w->SetFileName(f.c_str());
    REQUIRE(w->Write() == 1);
    INFO(name);
    const magenc::GridData g = magenc::read_grid_vti(f);
    REQUIRE(g.nodes() == 25);
    REQUIRE(g.has_B());
    for (std::size_t i = 0; i < 25; ++i) {
      CHECK(g.Bz_T[i] == Approx(0.01 * double(i)).margin(1e-15));
      CHECK(g.By_T[i] == Approx(-0.002 * double(i)).margin(1e-15));
    }
    ++layouts;
  }
  CHECK(layouts == 9);
}
