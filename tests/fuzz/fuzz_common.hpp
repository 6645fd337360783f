// Shared by the libFuzzer targets (tests/fuzz/fuzz_*.cpp, scripts/fuzz.sh). A reader may reject its
// input only with magenc::InputError; a crash, a sanitizer report, or any other exception escaping
// LLVMFuzzerTestOneInput (libFuzzer reports it as a deadly signal via std::terminate) is a finding.
#pragma once
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace magenc_fuzz {

// A private directory for this fuzzing process (removed at exit).
inline const std::filesystem::path& work_dir() {
  static const std::filesystem::path dir = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "magenc_fuzz.XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) std::abort();
    static const std::string keep = tmpl;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(keep, ec);
    });
    return std::filesystem::path(tmpl);
  }();
  return dir;
}

// Writes the fuzzer's bytes to work_dir()/name and returns that path.
inline std::filesystem::path write_input(const std::string& name, const uint8_t* data, size_t size) {
  const auto path = work_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) std::abort();
  return path;
}

}  // namespace magenc_fuzz
