// A folder of this process's own for the files a unit test writes. The regular run and the sanitizer
// run, or two workspaces, may run the same test at once: with a shared name in the temp folder, one
// would read what the other had just written (or removed).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace railvib::test {

class ScratchDir {
 public:
  /// <temp>/railvib_<purpose>_<pid>, created.
  explicit ScratchDir(const std::string& purpose)
      : path_(std::filesystem::temp_directory_path() / ("railvib_" + purpose + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  /// Removed with what it holds.
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// A file of the folder (not created).
  std::filesystem::path file(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace railvib::test
