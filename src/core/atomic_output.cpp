#include "core/atomic_output.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "core/errors.hpp"

namespace fs = std::filesystem;

namespace magenc {

namespace {
fs::path temp_name(const fs::path& p) {
  return fs::path(p.string() + ".tmp." + std::to_string(::getpid()));
}
// Removes "<name>.tmp.<digits>" and "<name>.old.<digits>" next to `path` (left by a killed run).
void remove_stale_temporaries(const fs::path& path) {
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string base = path.filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    for (const char* kind : {".tmp.", ".old."}) {
      const std::string prefix = base + kind;
      if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
          std::all_of(name.begin() + long(prefix.size()), name.end(), [](unsigned char c) { return std::isdigit(c); })) {
        std::error_code rm;
        fs::remove_all(it->path(), rm);
      }
    }
  }
}
}  // namespace

OutputLock::OutputLock(const fs::path& path) : lock_(path.string() + ".lock") {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  if (ec) throw InputError("--out " + path.string() + ": cannot create its parent directory (" + ec.message() + ")");
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw InputError("--out " + path.string() + ": cannot write here (" + std::strerror(errno) + ")");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd_);
      fd_ = -1;
      if (err == EWOULDBLOCK)
        throw InputError("--out " + path.string() + ": another magenc run is writing there (lock " + lock_.string() +
                         " is held): wait for it to finish or choose another --out");
      throw InputError("--out " + path.string() + ": cannot lock " + lock_.string() + " (" + std::strerror(err) + ")");
    }
    // The holder before us unlinks the lock file when done: make sure ours is still the one at lock_.
    struct stat held {}, now {};
    if (::fstat(fd_, &held) == 0 && ::stat(lock_.c_str(), &now) == 0 && held.st_ino == now.st_ino &&
        held.st_dev == now.st_dev) {
      remove_stale_temporaries(path);
      return;
    }
    ::close(fd_);
    fd_ = -1;
  }
  throw InputError("--out " + path.string() + ": cannot take the lock " + lock_.string());
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) {
    ::unlink(lock_.c_str());
    ::close(fd_);
  }
}

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)), tmp_(temp_name(path_)), lock_(path_) {
  std::error_code ec;
  if (fs::is_directory(path_, ec))
    throw InputError("--out " + path_.string() + " is a directory: allowed a file name");
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

AtomicDir::AtomicDir(fs::path dir) : dir_(std::move(dir)), tmp_(temp_name(dir_)), lock_(dir_) {
  std::error_code ec;
  if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
    throw InputError("--out " + dir_.string() + " is a file: allowed a directory (new or one to replace)");
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
    // Swap new and old in one step: there is no moment without a complete <dir>.
    if (::renameat2(AT_FDCWD, tmp_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      fs::remove_all(tmp_, ec);  // now the old <dir>
      return;
    }
    if (errno != EINVAL && errno != ENOSYS)
      throw ComputeError("--out " + dir_.string() + ": cannot replace it (" + std::strerror(errno) + ")");
    // A file system without RENAME_EXCHANGE: two renames (a kill between them leaves <dir>.old.<pid>
    // and <dir>.tmp.<pid>, both complete, which the next run removes).
    const fs::path old = fs::path(dir_.string() + ".old." + std::to_string(::getpid()));
    fs::rename(dir_, old);
    fs::rename(tmp_, dir_);
    committed_ = true;
    fs::remove_all(old, ec);
  } else {
    if (dir_.has_parent_path()) fs::create_directories(dir_.parent_path());
    fs::rename(tmp_, dir_);
    committed_ = true;
  }
}

}  // namespace magenc
