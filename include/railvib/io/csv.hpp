// railvib/io: CSV curves (header row + numeric rows), written atomically, read strictly.
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

/// Largest CSV file readCsv accepts (a 5 s Haren loads file is ~30 MB).
constexpr size_t kMaxCsvBytes = size_t{1} << 30;

/// A numeric CSV table read back (for loads files, profiles, records, tests and reports).
struct CsvTable {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  /// File line (1 = header) of each row, for messages.
  std::vector<size_t> line_of_row;
  /// Index of a named column; throws std::runtime_error naming the file and the columns if absent.
  size_t column(const std::string& name) const;
  /// "file.csv:12" for row i.
  std::string where(size_t row) const;
};

/// Read a CSV file strictly: a regular file of at most kMaxCsvBytes, unique non-empty column
/// names, every cell a whole finite number (no unit suffix such as "40000kN", no nan or inf, no
/// number cut short such as "1.5e"), every row as wide as the header, and a last line ended by a
/// newline (a file cut short is refused). Throws std::runtime_error naming the file, the line and
/// the cell.
CsvTable readCsv(const std::string& path);

/// The step of a uniformly sampled column (e.g. time): strictly increasing, every step within
/// 1 % of the mean step (CSV rounding). Throws naming the file, the line, the step found and the
/// mean step.
double uniformStep(const CsvTable& table, size_t column);

}  // namespace railvib::io
