// Config validation of the track section: malformed inputs are refused with a
// message naming the key path, the value, the allowed range and the file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "railvib/io/csv.hpp"
#include "railvib/track/track_analysis.hpp"
#include "railvib/track/track_stepper.hpp"
#include "test_scratch.hpp"
#include "track_test_util.hpp"

namespace fs = std::filesystem;

namespace railvib::track {
namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string tempDir() {
  static const railvib::test::ScratchDir scratch("track_test");
  return scratch.path().string();
}

TEST(TrackConfig, HarenLoads) {
  const TrackParams p = test::haren();
  EXPECT_EQ(p.foundation, FoundationModel::Clm);
  EXPECT_DOUBLE_EQ(p.rail_bending_stiffness_n_m2, 4.17e6);
  EXPECT_DOUBLE_EQ(p.clm.coupling_damping_n_s_m, -23.0e3);
  EXPECT_EQ(p.elements_per_bay, 4);
  const TrackParams w = test::haren({"track.foundation.model=winkler"});
  EXPECT_EQ(w.foundation, FoundationModel::Winkler);
  EXPECT_NEAR(w.winkler.stiffness_n_m, 32.0e6 / 0.26, 1.0);
  // The scenario file (with includes) loads too.
  const TrackParams s = loadTrackParams(Config::load(test::configPath("haren.yaml")).root());
  EXPECT_EQ(s.foundation, FoundationModel::Clm);
  const TrackModel model(p);
  EXPECT_GE(model.sleeperCount(), TrackParams::kMinSleepers);
  EXPECT_DOUBLE_EQ(model.sleeperPositions()[0] + 0.0, model.railStart());
}

struct BadCase {
  const char* name;
  const char* original;     // a unique snippet of config/track_haren.yaml
  const char* replacement;  // what replaces it
  const char* key;          // key path the message must name
  const char* detail;       // another fragment the message must contain (range, reason...)
};

class TrackConfigBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(TrackConfigBad, RefusedWithClearMessage) {
  const BadCase& c = GetParam();
  std::string text = readText(test::configPath("track_haren.yaml"));
  const size_t at = text.find(c.original);
  ASSERT_NE(at, std::string::npos) << "snippet not found: " << c.original;
  text.replace(at, std::string(c.original).size(), c.replacement);
  const std::string file = tempDir() + "/bad_" + c.name + ".yaml";
  {
    std::ofstream out(file);
    out << text;
  }
  try {
    // The cases that edit the extent replace its mode; the others get the fixed 100 m track.
    const bool edits_extent = std::string(c.original).find("mode: auto") != std::string::npos;
    const TrackParams p =
        loadTrackParams(Config::load(file, edits_extent ? std::vector<std::string>{} : test::fixedExtent()).root());
    (void)p;
    FAIL() << c.name << ": accepted";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(c.key), std::string::npos) << c.name << ": " << msg;
    EXPECT_NE(msg.find(c.detail), std::string::npos) << c.name << ": " << msg;
    EXPECT_NE(msg.find("bad_" + std::string(c.name) + ".yaml"), std::string::npos) << c.name << ": " << msg;
  }
  fs::remove(file);
}

INSTANTIATE_TEST_SUITE_P(
    Malformed, TrackConfigBad,
    ::testing::Values(
        BadCase{"missing_key", "    bending_stiffness_n_m2: 4.17e6\n", "", "track.rail.bending_stiffness_n_m2",
                "missing"},
        BadCase{"negative_mass", "    mass_kg: 45.0", "    mass_kg: -45.0", "track.sleeper.mass_kg", "-45"},
        BadCase{"nan", "    stiffness_n_m: 90.0e6", "    stiffness_n_m: .nan", "track.railpad.stiffness_n_m", "nan"},
        BadCase{"wrong_type", "    stiffness_n_m: 32.0e6", "    stiffness_n_m: soft", "track.ballast.stiffness_n_m",
                "soft"},
        BadCase{"zero_spacing", "    spacing_m: 0.72", "    spacing_m: 0", "track.sleeper.spacing_m", "[0.05, 5]"},
        BadCase{"unknown_foundation", "    model: clm", "    model: elastic", "track.foundation.model", "elastic"},
        BadCase{"x_max_below_x_min", "    mode: auto", "    mode: fixed\n    x_min_m: -50.0\n    x_max_m: -60.0",
                "track.extent.x_max_m", "greater than x_min_m"},
        BadCase{"zero_elements", "    elements_per_bay: 4", "    elements_per_bay: 0", "track.rail.elements_per_bay",
                "0"},
        BadCase{"fractional_elements", "    elements_per_bay: 4", "    elements_per_bay: 2.5",
                "track.rail.elements_per_bay", "2.5"},
        BadCase{"too_few_sleepers", "    mode: auto", "    mode: fixed\n    x_min_m: -2.0\n    x_max_m: 2.0",
                "track.extent.x_max_m", "at least 10"},
        BadCase{"negative_damping", "    damping_n_s_m: 30.0e3", "    damping_n_s_m: -30.0e3",
                "track.railpad.damping_n_s_m", "[0, "},
        BadCase{"coupling_damping_too_negative", "coupling_damping_n_s_m: -23.0e3", "coupling_damping_n_s_m: -50.0e3",
                "track.foundation.clm.coupling_damping_n_s_m", "d_f + 4 d_c"},
        BadCase{"infinite_mass", "    mass_per_length_kg_m: 54.0", "    mass_per_length_kg_m: .inf",
                "track.rail.mass_per_length_kg_m", "inf"},
        BadCase{"list_instead_of_number", "    spacing_m: 0.72", "    spacing_m: [0.72, 0.6]",
                "track.sleeper.spacing_m", "0.72"},
        BadCase{"usp_zero_modulus", "    bedding_modulus_n_mm3: 0.10", "    bedding_modulus_n_mm3: 0",
                "track.under_sleeper_pad.bedding_modulus_n_mm3", "[0.01, 2]"},
        BadCase{"ubm_negative_modulus", "    bedding_modulus_n_mm3: 0.03", "    bedding_modulus_n_mm3: -0.03",
                "track.under_ballast_mat.bedding_modulus_n_mm3", "-0.03"},
        BadCase{"ends_too_long", "    absorbing_length_m: 12.0", "    absorbing_length_m: 45.0",
                "track.ends.absorbing_length_m", "80 %"},
        BadCase{"negative_clm_mass",
                "    clm:\n      # per sleeper and half track [paper, appendix]\n      mass_kg: 2502.0",
                "    clm:\n      # per sleeper and half track [paper, appendix]\n      mass_kg: -1",
                "track.foundation.clm.mass_kg", "-1"},
        BadCase{"zero_load_rate", "load_sample_rate_hz: 2000.0", "load_sample_rate_hz: 0",
                "track.output.load_sample_rate_hz", "(0, "}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

// Overrides from the command line are validated the same way.
TEST(TrackConfig, OverrideValidated) {
  EXPECT_THROW(test::haren({"track.foundation.model=lumped"}), ConfigError);
  EXPECT_THROW(test::haren({"track.sleeper.spacing_m=-0.7"}), ConfigError);
  try {
    test::haren({"track.foundation.model=lumped"});
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("track.foundation.model"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("lumped"), std::string::npos);
  }
}

// A run that fails half-way leaves no partial CSV (io::AtomicFile).
TEST(TrackOutput, FailedRunLeavesNoPartialFile) {
  const std::string path = tempDir() + "/moving_load.csv";
  fs::remove(path);
  const TrackModel model(test::haren({"track.extent.mode=fixed", "track.extent.x_min_m=-15", "track.extent.x_max_m=15",
                                      "track.ends.absorbing_length_m=3"}));
  MovingLoadRun run;
  run.dt_s = 1e-3;
  run.duration_s = 10.0;  // the load leaves the 30 m rail after ~1.3 s
  run.front_start_m = 0.0;
  run.speed_m_s = 10.0;
  run.offsets_behind_m = {0.0};
  run.forces_n = {26e3};
  std::vector<std::string> columns{"t_s"};
  for (double x : model.sleeperPositions()) columns.push_back("x_" + std::to_string(x));
  long rows = 0;
  EXPECT_THROW(
      {
        io::CsvWriter csv(path, columns);
        simulateMovingLoads(model, run, [&](double t, const std::vector<double>& b) {
          std::vector<double> row{t};
          row.insert(row.end(), b.begin(), b.end());
          csv.row(row);
          ++rows;
        });
        csv.commit();
      },
      std::out_of_range);
  EXPECT_GT(rows, 100);  // it did write rows before failing
  EXPECT_FALSE(fs::exists(path));
  for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path())) {
    EXPECT_EQ(entry.path().string().find("moving_load"), std::string::npos) << "leftover " << entry.path();
  }
}

}  // namespace
}  // namespace railvib::track

namespace railvib::track {
namespace {

// The same through the real tool (subprocess): RAILVIB_TOOL, else the path the
// build gives (RAILVIB_TOOL_PATH), else next to this test binary.
std::string findTool() {
  if (const char* env = std::getenv("RAILVIB_TOOL")) return env;
#ifdef RAILVIB_TOOL_PATH
  if (fs::exists(RAILVIB_TOOL_PATH)) return RAILVIB_TOOL_PATH;
#endif
  const fs::path exe = fs::read_symlink("/proc/self/exe").parent_path();
  for (const fs::path& c :
       {exe.parent_path() / "bin" / "railvib_tool", exe.parent_path() / "devel" / "lib" / "railvib" / "railvib_tool"}) {
    if (fs::exists(c)) return c.string();
  }
  return "";
}

TEST(TrackTool, FailuresLeaveNoOutputFile) {
  const std::string tool = findTool();
  ASSERT_FALSE(tool.empty()) << "railvib_tool not found (the build makes it before test_track)";
  const std::string dir = tempDir();
  const std::string csv = dir + "/tool_out.csv";
  const std::string cfg = test::configPath("haren.yaml");
  struct Case {
    std::string args;
    int expected_status;
  };
  const std::vector<Case> cases{
      // bad config value: refused before any work (exit 3, ConfigError)
      {"moving-load --config " + cfg + " --set track.sleeper.spacing_m=0 --csv " + csv, 3},
      {"receptance --config " + cfg + " --foundation elastic --csv " + csv, 3},
      // a load leaves the rail half-way through the run: rows were written, then removed (exit 1)
      {"moving-load --config " + cfg +
           " --set track.extent.mode=fixed --set track.extent.x_min_m=-30 --set track.extent.x_max_m=30 "
           "--set track.ends.absorbing_length_m=5 --dt 1e-3 --rate 100 --duration 60 --csv " +
           csv,
       1},
  };
  for (const auto& c : cases) {
    fs::remove(csv);
    const std::string cmd = tool + " " + c.args + " > " + dir + "/stdout.txt 2> " + dir + "/stderr.txt";
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc)) << c.args;
    EXPECT_EQ(WEXITSTATUS(rc), c.expected_status) << c.args << "\n" << readText(dir + "/stderr.txt");
    EXPECT_FALSE(fs::exists(csv)) << c.args;
    for (const auto& entry : fs::directory_iterator(dir)) {
      EXPECT_EQ(entry.path().filename().string().find("tool_out"), std::string::npos) << "leftover " << entry.path();
    }
  }
  // and a good run writes the file
  const std::string good = tool + " moving-load --config " + cfg + " --dt 1e-3 --rate 100 --duration 0.5 --csv " + csv +
                           " > " + dir + "/stdout.txt";
  EXPECT_EQ(std::system(good.c_str()), 0);
  EXPECT_TRUE(fs::exists(csv));
  fs::remove(csv);
}

}  // namespace
}  // namespace railvib::track
