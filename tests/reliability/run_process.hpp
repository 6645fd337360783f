// Runs an executable (no shell) in a working directory, with stdout/stderr captured, an optional
// environment override and an optional kill after a delay. Used by the bad-input matrix, fault and
// determinism tests (tests/reliability/).
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace magenc_test {

namespace fs = std::filesystem;

struct ProcResult {
  int exit_code = -1;  // WEXITSTATUS, or -signal when killed by a signal
  std::string out, err;
  double seconds = 0;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A running child; wait() collects it, kill_after() sends SIGKILL at a given time.
class Child {
 public:
  Child(const fs::path& exe, const std::vector<std::string>& args, const fs::path& cwd,
        const std::map<std::string, std::string>& env = {}, const fs::path& capture_dir = {})
      : capture_(capture_dir.empty() ? cwd : capture_dir) {
    static int seq = 0;
    tag_ = std::to_string(::getpid()) + "_" + std::to_string(seq++);
    out_ = capture_ / ("stdout_" + tag_ + ".txt");
    err_ = capture_ / ("stderr_" + tag_ + ".txt");
    t0_ = std::chrono::steady_clock::now();
    pid_ = ::fork();
    if (pid_ == 0) {
      if (::chdir(cwd.c_str()) != 0) ::_exit(126);
      const int o = ::open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (o < 0 || e < 0) ::_exit(126);
      ::dup2(o, 1);
      ::dup2(e, 2);
      for (const auto& [k, v] : env) ::setenv(k.c_str(), v.c_str(), 1);
      std::vector<std::string> argv_s{exe.string()};
      argv_s.insert(argv_s.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (auto& a : argv_s) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(exe.c_str(), argv.data());
      ::_exit(127);
    }
  }
  void kill_after(double seconds) {
    std::this_thread::sleep_until(t0_ + std::chrono::duration<double>(seconds));
    ::kill(pid_, SIGKILL);
  }
  ProcResult wait() {
    int status = 0;
    ::waitpid(pid_, &status, 0);
    ProcResult r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? -WTERMSIG(status) : -1000;
    r.out = slurp(out_);
    r.err = slurp(err_);
    std::error_code ec;
    fs::remove(out_, ec);
    fs::remove(err_, ec);
    return r;
  }

 private:
  fs::path capture_, out_, err_;
  std::string tag_;
  pid_t pid_ = -1;
  std::chrono::steady_clock::time_point t0_;
};

inline ProcResult run(const fs::path& exe, const std::vector<std::string>& args, const fs::path& cwd,
                      const std::map<std::string, std::string>& env = {}, const fs::path& capture_dir = {}) {
  return Child(exe, args, cwd, env, capture_dir).wait();
}

// A scratch directory, removed afterwards.
struct ScratchDir {
  fs::path dir;
  explicit ScratchDir(const std::string& prefix) {
    static int seq = 0;
    dir = fs::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(seq++));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
  }
  // Entries of dir (recursively) other than the given input names.
  std::vector<std::string> entries_except(const std::vector<std::string>& inputs) const {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      const std::string rel = fs::relative(e.path(), dir).string();
      bool input = false;
      for (const auto& i : inputs) input = input || rel == i || rel.rfind(i + "/", 0) == 0;
      if (!input) out.push_back(rel);
    }
    return out;
  }
};

// The executables under test: every file of build/bin except the benchmarks.
inline std::vector<fs::path> executables(const fs::path& bin_dir) {
  std::vector<fs::path> exes;
  for (const auto& e : fs::directory_iterator(bin_dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.rfind("bench_", 0) != 0 && ::access(e.path().c_str(), X_OK) == 0)
      exes.push_back(e.path());
  }
  std::sort(exes.begin(), exes.end());
  return exes;
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  if (!s.empty() && s.back() != '\n') ++n;
  return n;
}

}  // namespace magenc_test
