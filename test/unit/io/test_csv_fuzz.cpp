// The strict CSV reader: what it refuses (each with file, line and cell) and a property fuzz:
// random and adversarial mutations of a valid loads file (cut short, NaN/inf, unit suffixes,
// huge, reordered, duplicated rows, garbage bytes) are refused by name or read into a table whose
// every value is finite and every row as wide as the header; a file cut mid-line is always
// refused. Run under AddressSanitizer too (./railvib test).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "railvib/io/csv.hpp"
#include "test_scratch.hpp"

namespace fs = std::filesystem;
using railvib::io::CsvTable;
using railvib::io::readCsv;
using railvib::io::uniformStep;

namespace {

fs::path tempFile(const std::string& name) {
  static const railvib::test::ScratchDir scratch("csvfuzz");
  return scratch.file(name);
}

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string errorOf(const fs::path& path) {
  try {
    readCsv(path.string());
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

std::string loadsText(size_t rows, size_t sleepers) {
  std::ostringstream s;
  s.precision(12);
  s << "t_s";
  for (size_t j = 0; j < sleepers; ++j) s << ",sleeper_" << j;
  s << "\n";
  for (size_t i = 0; i < rows; ++i) {
    s << static_cast<double>(i) * 5e-4;
    for (size_t j = 0; j < sleepers; ++j) s << "," << 1000.0 * static_cast<double>(i + j) + 0.125;
    s << "\n";
  }
  return s.str();
}

}  // namespace

TEST(CsvStrict, RefusesWhatIsNotAPlainFiniteNumberNamingLineAndColumn) {
  const fs::path p = tempFile("strict.csv");
  auto expect = [&](const std::string& text, const std::vector<std::string>& parts) {
    writeText(p, text);
    const std::string e = errorOf(p);
    ASSERT_FALSE(e.empty()) << "accepted: " << text;
    EXPECT_NE(e.find(p.string()), std::string::npos) << e;
    for (const auto& part : parts) EXPECT_NE(e.find(part), std::string::npos) << part << " not in: " << e;
  };
  expect("t_s,f\n0,40000kN\n", {":2", "column 'f'", "'40000kN' is not a number"});
  expect("t_s,f\n0,nan\n", {":2", "'nan' is not a finite number"});
  expect("t_s,f\n0,-inf\n", {"not a finite number"});
  expect("t_s,f\n0,1e400\n", {"not a finite number"});
  expect("t_s,f\n0,1.5e\n", {"'1.5e' is not a number"});
  expect("t_s,f\n0,\n", {"'' is not a number"});
  expect("t_s,f\n0,1\n0.1,2", {":3", "no end of line", "cut short"});
  expect("t_s,f", {":1", "no end of line"});
  expect("t_s,t_s\n0,1\n", {"column 't_s' appears twice"});
  expect("t_s,,f\n", {"empty column name"});
  expect("t_s,f\n0,1,2\n", {"expected 2 values, got 3"});
  expect("", {"empty CSV file"});
  EXPECT_NE(errorOf(fs::temp_directory_path()).find("is a directory"), std::string::npos);
  EXPECT_NE(errorOf(tempFile("absent.csv")).find("no such file"), std::string::npos);
  fs::remove(p);
}

TEST(CsvStrict, ReadsSpacesCrLfBomAndSubnormals) {
  const fs::path p = tempFile("ok.csv");
  writeText(p, "\xEF\xBB\xBFt_s, vz\r\n0, 1.5\r\n\r\n1e-3,-8.6e-309\r\n");
  const CsvTable t = readCsv(p.string());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.column("vz"), 1u);
  EXPECT_EQ(t.line_of_row[1], 4u);
  EXPECT_DOUBLE_EQ(t.rows[1][1], -8.6e-309);
  fs::remove(p);
}

TEST(CsvStrict, UniformStepChecksEveryRow) {
  const fs::path p = tempFile("step.csv");
  writeText(p, "t_s,v\n0,0\n0.001,0\n0.002,0\n0.0025,0\n0.004,0\n");
  const std::string nonuniform = [&] {
    try {
      uniformStep(readCsv(p.string()), 0);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_NE(nonuniform.find(":5"), std::string::npos) << nonuniform;  // the row of the short step
  EXPECT_NE(nonuniform.find("uniformly spaced"), std::string::npos);
  writeText(p, "t_s,v\n0,0\n0.001,0\n0.002,0\n0.001,0\n0.004,0\n");  // goes back
  EXPECT_THROW(uniformStep(readCsv(p.string()), 0), std::runtime_error);
  writeText(p, "t_s,v\n0,0\n0.001,0\n0.002,0\n0.003,0\n0.004,0\n");
  EXPECT_NEAR(uniformStep(readCsv(p.string()), 0), 1e-3, 1e-15);
  fs::remove(p);
}

TEST(CsvFuzz, MutatedLoadsFilesAreRefusedByNameOrReadWhole) {
  std::mt19937_64 rng(4150);
  const std::string good = loadsText(40, 5);
  const fs::path p = tempFile("fuzz.csv");
  const std::vector<std::string> junk{"nan", "inf",   "-inf",  "1e400",    "40000kN", "1.5e",  "0x", "--1", "1,",
                                      ",",   "\"3\"", "1e300", "\x01\x02", "  ",      "1.2.3", "+",  "e5",  "\xff"};
  size_t refused = 0, accepted = 0;
  for (int iteration = 0; iteration < 3000; ++iteration) {
    std::string text = good;
    bool cut_mid_line = false;
    const int mutations = 1 + static_cast<int>(rng() % 3);
    for (int m = 0; m < mutations; ++m) {
      switch (rng() % 6) {
        case 0: {  // cut short anywhere
          const size_t at = rng() % (text.size() + 1);
          text.resize(at);
          cut_mid_line = !text.empty() && text.back() != '\n';
          break;
        }
        case 1: {  // a junk token in place of a cell
          const size_t at = rng() % text.size();
          text.insert(at, junk[rng() % junk.size()]);
          break;
        }
        case 2: {  // a random byte replaced
          if (!text.empty()) text[rng() % text.size()] = static_cast<char>(rng() % 256);
          break;
        }
        case 3: {  // a line duplicated (time column no longer increasing)
          const size_t start = text.find('\n', rng() % text.size());
          if (start != std::string::npos && start + 1 < text.size()) {
            const size_t end = text.find('\n', start + 1);
            if (end != std::string::npos) text.insert(start + 1, text.substr(start + 1, end - start));
          }
          break;
        }
        case 4: {  // a line dropped
          const size_t start = text.find('\n', rng() % text.size());
          const size_t end = start == std::string::npos ? start : text.find('\n', start + 1);
          if (end != std::string::npos) text.erase(start + 1, end - start);
          break;
        }
        default:  // a huge value
          text.insert(text.rfind(',') + 1, "9");
          break;
      }
      if (cut_mid_line) break;  // the last mutation decides whether the end is cut
    }
    if (!text.empty() && text.back() != '\n') cut_mid_line = true;
    writeText(p, text);
    try {
      const CsvTable t = readCsv(p.string());
      ASSERT_FALSE(cut_mid_line) << "a file cut mid-line was accepted (iteration " << iteration << ")";
      for (const auto& row : t.rows) {
        ASSERT_EQ(row.size(), t.columns.size());
        for (double v : row) ASSERT_TRUE(std::isfinite(v));
      }
      ++accepted;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_GT(refused, 1000u);
  EXPECT_GT(accepted, 100u);
  fs::remove(p);
}
