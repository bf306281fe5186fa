// railvib/io: CSV curves (header row + numeric rows), written atomically.
#pragma once

#include <string>
#include <vector>

#include "railvib/io/atomic_file.hpp"

namespace railvib::io {

class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& columns);
  void row(const std::vector<double>& values);
  void commit() { file_.commit(); }

 private:
  AtomicFile file_;
  size_t column_count_;
};

/// A numeric CSV table read back (for loads files, tests and reports).
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  /// Index of a named column; throws std::runtime_error if absent.
  size_t column(const std::string& name) const;
};

CsvTable readCsv(const std::string& path);

}  // namespace railvib::io
