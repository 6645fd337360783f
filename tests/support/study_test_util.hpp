// Helpers for the study smoke tests: run a study executable, read CSV tables.
#pragma once
#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace magenc::test {

namespace fs = std::filesystem;

struct StudyRun {
  int code;         // exit code (-1 if killed)
  std::string err;  // stderr text
};

// Runs MAGENC_BIN_DIR/<study> --out <out> <args>, stdout discarded.
inline StudyRun run_study_exe(const std::string& study, const fs::path& out, const std::string& args) {
  const fs::path err = fs::temp_directory_path() / (study + "_" + std::to_string(::getpid()) + ".stderr");
  const std::string cmd = std::string(MAGENC_BIN_DIR) + "/" + study + " --out '" + out.string() + "' " + args +
                          " >/dev/null 2>'" + err.string() + "'";
  const int rc = std::system(cmd.c_str());
  std::ifstream f(err);
  std::stringstream ss;
  ss << f.rdbuf();
  fs::remove(err);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

// A fresh temp directory path (not created) for one test.
inline fs::path temp_out(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("magenc_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

// CHECKs that each of `files` exists in out (the missing one named in the failure).
inline void check_files_exist(const fs::path& out, std::initializer_list<const char*> files) {
  for (const char* f : files) {
    INFO(f);
    CHECK(fs::exists(out / f));
  }
}

// Any "<out>.tmp.*" / "<out>.old.*" siblings left behind?
inline bool leftovers(const fs::path& out) {
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    if (e.path().filename().string().rfind(out.filename().string() + ".", 0) == 0) return true;
  return false;
}

// A CSV file as rows of column -> text (header row gives the names; no quoting).
inline std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& line) {
    std::vector<std::string> v;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(c);
    return v;
  };
  std::string line;
  if (!std::getline(in, line)) return rows;
  const auto header = split(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto cells = split(line);
    std::map<std::string, std::string> r;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) r[header[i]] = cells[i];
    rows.push_back(std::move(r));
  }
  return rows;
}

inline double num(const std::map<std::string, std::string>& row, const std::string& col) {
  return std::stod(row.at(col));
}

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace magenc::test
