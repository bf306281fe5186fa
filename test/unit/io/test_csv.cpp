#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "railvib/io/csv.hpp"
#include "test_scratch.hpp"

namespace fs = std::filesystem;
using railvib::io::CsvWriter;
using railvib::io::readCsv;

namespace {
// This process's own folder: the regular and the sanitizer run may write these files at once.
fs::path csvScratchFile(const std::string& name) {
  static const railvib::test::ScratchDir scratch("csv");
  return scratch.file(name);
}
}  // namespace

TEST(Csv, RoundTripsValuesIncludingSubnormals) {
  const fs::path path = csvScratchFile("roundtrip.csv");
  {
    CsvWriter w(path.string(), {"t_s", "v"});
    w.row({0.0, -8.6e-309});
    w.row({1e-3, 1.25});
    w.commit();
  }
  const auto table = readCsv(path.string());
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.column("v"), 1u);
  EXPECT_DOUBLE_EQ(table.rows[0][1], -8.6e-309);
  EXPECT_DOUBLE_EQ(table.rows[1][1], 1.25);
  fs::remove(path);
}

TEST(Csv, UncommittedFileLeavesNothingBehind) {
  const fs::path path = csvScratchFile("uncommitted.csv");
  fs::remove(path);
  {
    CsvWriter w(path.string(), {"a"});
    w.row({1.0});
  }  // destroyed without commit(), as when a run throws half way
  EXPECT_FALSE(fs::exists(path));
  for (const auto& entry : fs::directory_iterator(path.parent_path())) {
    EXPECT_EQ(entry.path().filename().string().rfind("uncommitted.csv.tmp", 0), std::string::npos);
  }
}

TEST(Csv, RejectsMalformedRows) {
  const fs::path path = csvScratchFile("bad.csv");
  std::ofstream(path) << "a,b\n1,2\n3,x\n";
  EXPECT_THROW(readCsv(path.string()), std::runtime_error);
  std::ofstream(path) << "a,b\n1,2,3\n";
  EXPECT_THROW(readCsv(path.string()), std::runtime_error);
  fs::remove(path);
}

TEST(Csv, ReadsCrLfFiles) {
  const fs::path path = csvScratchFile("crlf.csv");
  std::ofstream(path) << "t_s,vz\r\n0,1.5\r\n";
  const auto table = readCsv(path.string());
  EXPECT_EQ(table.column("vz"), 1u);
  EXPECT_DOUBLE_EQ(table.rows.at(0).at(1), 1.5);
  fs::remove(path);
}
