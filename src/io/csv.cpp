#include "railvib/io/csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace railvib::io {

namespace {

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

std::string shown(const std::string& cell) { return cell.size() > 40 ? cell.substr(0, 37) + "..." : cell; }

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

}  // namespace

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
  std::string list;
  for (const auto& c : columns) list += (list.empty() ? "" : ", ") + c;
  if (list.size() > 200) list = list.substr(0, 197) + "...";
  throw std::runtime_error(path + ": no column '" + name + "' (columns: " + list + ")");
}

std::string CsvTable::where(size_t row) const {
  return path + ":" + std::to_string(row < line_of_row.size() ? line_of_row[row] : 0);
}

CsvTable readCsv(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) throw std::runtime_error("cannot read " + path + ": no such file");
  if (std::filesystem::is_directory(status)) throw std::runtime_error(path + " is a directory, not a CSV file");
  if (!std::filesystem::is_regular_file(status)) throw std::runtime_error(path + " is not a regular file");
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxCsvBytes) {
    throw std::runtime_error(path + ": " + std::to_string(size) + " bytes, more than the " +
                             std::to_string(kMaxCsvBytes) + " a CSV file may have");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path + ": " + std::strerror(errno));
  CsvTable table;
  table.path = path;
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path + ": empty CSV file (a header row is expected)");
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);   // UTF-8 byte order mark (spreadsheets)
  if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF files (spreadsheets, Python's csv)
  std::set<std::string> seen;
  for (const std::string& cell : splitCells(line)) {
    const std::string name = trimmed(cell);
    if (name.empty()) throw std::runtime_error(path + ":1: empty column name in the header '" + shown(line) + "'");
    if (!seen.insert(name).second) throw std::runtime_error(path + ":1: column '" + name + "' appears twice");
    table.columns.push_back(name);
  }
  if (in.eof()) throw std::runtime_error(path + ":1: the header has no end of line (file cut short?)");
  size_t line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    // getline stops at the end of the file without a newline: the last line was cut short.
    if (in.eof()) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": the last line '" + shown(line) +
                               "' has no end of line (file cut short?)");
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trimmed(line).empty()) continue;
    std::vector<double> row;
    const std::vector<std::string> cells = splitCells(line);
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string cell = trimmed(cells[c]);
      const std::string at = path + ":" + std::to_string(line_no) + ": column " +
                             (c < table.columns.size() ? "'" + table.columns[c] + "'" : std::to_string(c + 1));
      // strtod, not stod: stod refuses subnormal values (ERANGE on underflow), which are valid numbers here.
      const char* begin = cell.c_str();
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (cell.empty() || end != begin + cell.size()) {
        throw std::runtime_error(at + ": '" + shown(cell) +
                                 "' is not a number (plain numbers only, in the unit of the column name)");
      }
      if (!std::isfinite(v)) throw std::runtime_error(at + ": '" + shown(cell) + "' is not a finite number");
      row.push_back(v);
    }
    if (row.size() != table.columns.size()) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " +
                               std::to_string(table.columns.size()) + " values, got " + std::to_string(row.size()));
    }
    table.rows.push_back(std::move(row));
    table.line_of_row.push_back(line_no);
  }
  if (in.bad()) throw std::runtime_error("cannot read " + path + ": read error");
  return table;
}

double uniformStep(const CsvTable& table, size_t column) {
  const auto& rows = table.rows;
  if (rows.size() < 2) throw std::runtime_error(table.path + ": at least 2 rows are needed for a sample step");
  const std::string name = table.columns.at(column);
  const double mean = (rows.back()[column] - rows.front()[column]) / static_cast<double>(rows.size() - 1);
  // Order first (a repeated or reordered row is named as such), then spacing.
  for (size_t i = 1; i < rows.size(); ++i) {
    if (!(rows[i][column] > rows[i - 1][column])) {
      throw std::runtime_error(table.where(i) + ": " + name + " = " + fmt(rows[i][column]) +
                               " does not increase (previous row " + fmt(rows[i - 1][column]) + ")");
    }
  }
  for (size_t i = 1; i < rows.size(); ++i) {
    const double d = rows[i][column] - rows[i - 1][column];
    if (std::abs(d - mean) > 0.01 * mean) {
      throw std::runtime_error(table.where(i) + ": " + name + " steps by " + fmt(d) + " here, the mean step is " +
                               fmt(mean) + ": the samples must be uniformly spaced (resample first)");
    }
  }
  return mean;
}

}  // namespace railvib::io
