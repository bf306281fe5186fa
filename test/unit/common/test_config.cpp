#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "config_test_util.hpp"
#include "railvib/common/config.hpp"
#include "test_scratch.hpp"

using railvib::Config;
using railvib::ConfigError;
using railvib::Range;
using railvib::testing::writeFile;

namespace {

// Expect a ConfigError whose message contains every fragment.
void expectConfigError(const std::function<void()>& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

// This process's own folder for the files these tests write (the sanitizer run may run them at once).
std::filesystem::path configScratchDir(const std::string& name) {
  static const railvib::test::ScratchDir scratch("config");
  return scratch.file(name);
}
}  // namespace

TEST(Range, ContainsAndDescribesBounds) {
  EXPECT_TRUE(Range::positive().contains(1e-12));
  EXPECT_FALSE(Range::positive().contains(0.0));
  EXPECT_TRUE(Range::nonNegative().contains(0.0));
  EXPECT_FALSE(Range::closed(0, 0.5).contains(std::nan("")));
  EXPECT_TRUE(Range::closed(0, 0.5).contains(0.5));
  EXPECT_FALSE(Range::open(-1, 0.5).contains(0.5));
  EXPECT_EQ(Range::positive().describe(), "(0, inf)");
  EXPECT_EQ(Range::closed(1, 2).describe(), "[1, 2]");
}

TEST(Config, ReadsTypedValuesWithRanges) {
  const Config c =
      Config::fromString("track:\n  rail:\n    mass_kg: 54\n    n: 4\n  model: clm\n  on: true\n  v: [1, 2]\n");
  const auto rail = c.section("track").section("rail");
  EXPECT_DOUBLE_EQ(rail.number("mass_kg", Range::positive()), 54.0);
  EXPECT_EQ(rail.integer("n", 1, 10), 4);
  EXPECT_EQ(c.section("track").choice("model", {"clm", "winkler"}), "clm");
  EXPECT_TRUE(c.section("track").flag("on"));
  EXPECT_EQ(c.section("track").numbers("v", Range::any()).size(), 2u);
  EXPECT_DOUBLE_EQ(rail.number("absent_m", Range::positive(), 3.5), 3.5);
}

TEST(Config, ErrorsNameKeyPathValueRangeAndFile) {
  const Config c = Config::fromString(
      "track:\n  mass_kg: -3\n  nan_value: .nan\n  text_value: abc\n  model: bogus\n  n: 2.5\n  list: [1, x]\n",
      "cfg.yaml");
  const auto t = c.section("track");
  expectConfigError([&] { t.number("mass_kg", Range::positive()); }, {"track.mass_kg", "-3", "(0, inf)", "cfg.yaml"});
  expectConfigError([&] { t.number("nan_value", Range::any()); }, {"track.nan_value", "finite"});
  expectConfigError([&] { t.number("text_value", Range::any()); }, {"track.text_value", "abc", "number"});
  expectConfigError([&] { t.number("missing_m", Range::any()); }, {"track.missing_m", "missing"});
  expectConfigError([&] { t.choice("model", {"clm", "winkler"}); }, {"track.model", "bogus", "clm, winkler"});
  expectConfigError([&] { t.integer("n", 1, 10); }, {"track.n", "2.5", "integer"});
  expectConfigError([&] { t.numbers("list", Range::any()); }, {"track.list", "x"});
  expectConfigError([&] { t.section("mass_kg"); }, {"track.mass_kg", "map"});
  expectConfigError([&] { t.fail("mass_kg", "must exceed the sleeper mass"); }, {"track.mass_kg", "sleeper"});
}

TEST(Config, IncludesMergeAndOverridesWinWithTheirSourceNamed) {
  const auto dir = configScratchDir("includes");
  writeFile(dir, "base.yaml", "track:\n  a_m: 1.0\n  b_m: 2.0\n");
  const auto top = writeFile(dir, "top.yaml", "include: [base.yaml]\ntrack:\n  b_m: 3.0\n");
  const Config c = Config::load(top.string(), {"track.a_m=-7"});
  const auto t = c.section("track");
  EXPECT_DOUBLE_EQ(t.number("b_m", Range::any()), 3.0);  // including file overrides include
  EXPECT_NE(t.fileOf("b_m").find("top.yaml"), std::string::npos);
  expectConfigError([&] { t.number("a_m", Range::positive()); }, {"track.a_m", "-7", "command-line override"});
  // An untouched key keeps the file it came from.
  const Config c2 = Config::load(top.string());
  expectConfigError([&] { c2.section("track").number("a_m", Range::greaterThan(5)); }, {"base.yaml"});
  std::filesystem::remove_all(dir);
}

TEST(Config, RejectsIncludeCyclesMissingFilesAndBadYaml) {
  const auto dir = configScratchDir("cycle");
  writeFile(dir, "a.yaml", "include: [b.yaml]\n");
  writeFile(dir, "b.yaml", "include: [a.yaml]\n");
  writeFile(dir, "bad.yaml", "track: [unclosed\n");
  writeFile(dir, "ok.yaml", "track: {a_m: 1}\n");
  expectConfigError([&] { Config::load((dir / "a.yaml").string()); }, {"cycle"});
  expectConfigError([&] { Config::load((dir / "none.yaml").string()); }, {"not found"});
  expectConfigError([&] { Config::load((dir / "bad.yaml").string()); }, {"bad.yaml", "YAML"});
  expectConfigError([&] { Config::load((dir / "ok.yaml").string(), {"novalue"}); }, {"key.path=value"});
  std::filesystem::remove_all(dir);
}

TEST(Config, HarenScenarioLoadsAndCarriesPaperValues) {
  const Config c = Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml");
  // Spot checks of the paper's appendix values reaching the merged tree.
  EXPECT_DOUBLE_EQ(c.section("track").section("ballast").number("stiffness_n_m", Range::positive()), 32.0e6);
  EXPECT_DOUBLE_EQ(c.section("vehicles")
                       .section("t2000")
                       .section("bodies")
                       .section("front_carbody")
                       .number("mass_kg", Range::positive()),
                   7580.0);
  EXPECT_DOUBLE_EQ(c.section("soil").number("rayleigh_beta_s", Range::nonNegative()), 4.0e-4);
  EXPECT_NEAR(c.section("simulation").number("speed_m_s", Range::positive()) * 3.6, 30.0, 1e-9);
}

#include "railvib/common/site.hpp"

TEST(SiteLayout, PlacesBuildingFourMetresFromExteriorRail) {
  const Config c = Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml");
  const railvib::SiteLayout site = railvib::loadSiteLayout(c.root());
  ASSERT_TRUE(site.building.has_value());
  EXPECT_NEAR(site.building->origin_y_m - site.exterior_rail_y_m, 4.0, 1e-12);  // [paper]
  EXPECT_NEAR(site.exterior_rail_y_m, 1.435 / 2, 1e-12);
  EXPECT_NEAR(site.building->origin_x_m, -5.0, 1e-12);  // 10 m front wall centred on the defect
  EXPECT_NEAR(site.building->trackX(7.5), 2.5, 1e-12);
  ASSERT_EQ(site.ground_sensors.size(), 2u);
  EXPECT_EQ(site.ground_sensors[0].name, "ground_2m");
  EXPECT_NEAR(site.ground_sensors[1].y_m, 8.0, 1e-12);
}

TEST(SiteLayout, RejectsDuplicateSensorNames) {
  const Config c = Config::fromString(
      "building: {length_m: 10, width_m: 7}\nsite:\n  rail_gauge_m: 1.435\n  building: {center_x_m: 0, "
      "front_wall_distance_from_rail_m: 4}\n"
      "  ground_sensors:\n    - {name: a, x_m: 0, y_m: 2}\n    - {name: a, x_m: 0, y_m: 8}\n");
  EXPECT_THROW(railvib::loadSiteLayout(c.root()), ConfigError);
}

TEST(SiteLayout, NoHouseWithoutBuildingSection) {
  const Config c = Config::fromString("site: {rail_gauge_m: 1.0, ground_sensors: [{name: a, x_m: 0, y_m: 2}]}\n");
  const railvib::SiteLayout site = railvib::loadSiteLayout(c.root());
  EXPECT_FALSE(site.building.has_value());
  EXPECT_DOUBLE_EQ(site.exterior_rail_y_m, 0.5);
}

TEST(TrackLayout, SleeperRuleHoldsTheExtentEnds) {
  // 0.72 m spacing from an offset of 0.1 m over [-1, 2]: k = -1 .. 2 (x = -0.62 .. 1.54), an end
  // exactly on a sleeper included despite rounding.
  const Config c = Config::fromString(
      "track: {sleeper: {spacing_m: 0.72, offset_m: 0.1, length_m: 2.6, width_m: 0.25}, "
      "extent: {mode: fixed, x_min_m: -1.0, x_max_m: 1.54}}\n");
  const railvib::TrackLayout t = railvib::loadTrackLayout(c.root());
  const std::vector<double> x = t.sleeperPositions();
  ASSERT_EQ(x.size(), 4u);
  EXPECT_EQ(t.sleeperCount(), 4);
  EXPECT_NEAR(x.front(), -0.62, 1e-12);
  EXPECT_NEAR(x.back(), 1.54, 1e-12);
  for (size_t i = 1; i < x.size(); ++i) EXPECT_NEAR(x[i] - x[i - 1], 0.72, 1e-12);
}
