#include "railvib/io/csv.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace railvib::io {

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns)
    : file_(path), column_count_(columns.size()) {
  auto& out = file_.stream();
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << "\n";
}

void CsvWriter::row(const std::vector<double>& values) {
  if (values.size() != column_count_) {
    throw std::logic_error("CSV row has " + std::to_string(values.size()) + " values, header has " +
                           std::to_string(column_count_));
  }
  auto& out = file_.stream();
  for (size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << values[i];
  out << "\n";
}

size_t CsvTable::column(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return i;
  }
  throw std::runtime_error("CSV has no column '" + name + "'");
}

CsvTable readCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  CsvTable table;
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path + ": empty CSV file");
  if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF files (spreadsheets, Python's csv)
  {
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) table.columns.push_back(cell);
  }
  size_t line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) {
      // strtod, not stod: stod refuses subnormal values (ERANGE on underflow), which are valid numbers here.
      const char* begin = cell.c_str();
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      const size_t used = static_cast<size_t>(end - begin);
      if (used == 0) throw std::runtime_error(path + ":" + std::to_string(line_no) + ": not a number: '" + cell + "'");
      row.push_back(v);
    }
    if (row.size() != table.columns.size()) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " +
                               std::to_string(table.columns.size()) + " values, got " + std::to_string(row.size()));
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace railvib::io
