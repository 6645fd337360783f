// No partial output on failure: write to a temporary name, rename on success.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>

namespace magenc {

// A file written under "<path>.tmp.<pid>" and renamed to <path> by commit().
// If commit() is never reached (exception), the destructor removes the temp.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::ostream& stream() { return out_; }
  const std::filesystem::path& temp_path() const { return tmp_; }
  void commit();

 private:
  std::filesystem::path path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes text to path atomically.
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

// An output directory built under "<dir>.tmp.<pid>" and swapped in place of
// <dir> by commit() (an old <dir> is removed only then). On failure the
// destructor removes the temporary directory and leaves any old <dir> intact.
class AtomicDir {
 public:
  explicit AtomicDir(std::filesystem::path dir);
  ~AtomicDir();
  AtomicDir(const AtomicDir&) = delete;
  AtomicDir& operator=(const AtomicDir&) = delete;
  // Where to write files now (the temporary directory).
  const std::filesystem::path& path() const { return tmp_; }
  std::filesystem::path operator/(const std::string& name) const { return tmp_ / name; }
  const std::filesystem::path& final_path() const { return dir_; }
  void commit();

 private:
  std::filesystem::path dir_, tmp_;
  bool committed_ = false;
};

}  // namespace magenc
