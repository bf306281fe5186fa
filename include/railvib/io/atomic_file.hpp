// railvib/io: output files that appear whole or not at all.
//
// Results are written to a temporary sibling and renamed into place by
// commit(); if anything throws before that, the destructor removes the
// temporary, so a failed run never leaves a partial output file behind.
#pragma once

#include <fstream>
#include <string>

namespace railvib::io {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path, std::ios::openmode mode = std::ios::out);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  const std::string& path() const { return path_; }
  /// Flush, close and rename into place. Throws std::runtime_error on I/O failure.
  void commit();

 private:
  std::string path_;
  std::string temp_path_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace railvib::io
