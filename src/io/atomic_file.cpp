#include "railvib/io/atomic_file.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace railvib::io {

AtomicFile::AtomicFile(std::string path, std::ios::openmode mode)
    : path_(std::move(path)), temp_path_(path_ + ".tmp." + std::to_string(::getpid())) {
  const auto parent = std::filesystem::path(path_).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  out_.open(temp_path_, mode | std::ios::out | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + path_);
  out_.precision(12);
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::remove(temp_path_.c_str());
  }
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw std::runtime_error("write failed: " + path_ + " (disk full?)");
  out_.close();
  if (!out_) throw std::runtime_error("write failed: " + path_ + " (disk full?)");
  std::filesystem::rename(temp_path_, path_);
  committed_ = true;
}

}  // namespace railvib::io
