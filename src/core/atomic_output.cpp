#include "core/atomic_output.hpp"

#include <unistd.h>

#include "core/errors.hpp"

namespace fs = std::filesystem;

namespace magenc {

namespace {
fs::path temp_name(const fs::path& p) {
  return fs::path(p.string() + ".tmp." + std::to_string(::getpid()));
}
}  // namespace

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)), tmp_(temp_name(path_)) {
  if (path_.has_parent_path()) fs::create_directories(path_.parent_path());
  out_.open(tmp_, std::ios::binary);
  if (!out_) throw InputError("--out " + path_.string() + ": cannot write here");
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw ComputeError("writing " + path_.string() + " failed");
  out_.close();
  fs::rename(tmp_, path_);
  committed_ = true;
}

void write_file_atomic(const fs::path& path, const std::string& text) {
  AtomicFile f(path);
  f.stream() << text;
  f.commit();
}

AtomicDir::AtomicDir(fs::path dir) : dir_(std::move(dir)), tmp_(temp_name(dir_)) {
  std::error_code ec;
  fs::remove_all(tmp_, ec);
  fs::create_directories(tmp_, ec);
  if (ec) throw InputError("--out " + dir_.string() + ": cannot create directory (" + ec.message() + ")");
}

AtomicDir::~AtomicDir() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(tmp_, ec);
  }
}

void AtomicDir::commit() {
  std::error_code ec;
  if (fs::exists(dir_)) {
    const fs::path old = fs::path(dir_.string() + ".old." + std::to_string(::getpid()));
    fs::rename(dir_, old);
    fs::rename(tmp_, dir_);
    fs::remove_all(old, ec);
  } else {
    if (dir_.has_parent_path()) fs::create_directories(dir_.parent_path());
    fs::rename(tmp_, dir_);
  }
  committed_ = true;
}

}  // namespace magenc
