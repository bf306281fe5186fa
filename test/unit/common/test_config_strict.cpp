// Config strictness: unknown keys (with the nearest valid key), repeated keys, aliases, sizes,
// paths that are not files. The loaders record what they read; what they never asked for is a
// typo.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "config_test_util.hpp"
#include "railvib/common/config.hpp"
#include "test_scratch.hpp"

using railvib::Config;
using railvib::ConfigError;
using railvib::Range;
using railvib::testing::writeFile;
namespace fs = std::filesystem;

namespace {

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

void expectContains(const std::string& message, const std::vector<std::string>& fragments) {
  EXPECT_FALSE(message.empty()) << "expected a ConfigError";
  for (const auto& f : fragments) EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
}

// A folder of its own for each test's files (created), in this process's scratch folder.
fs::path tempDir(const std::string& name) {
  static const railvib::test::ScratchDir scratch("strict");
  const fs::path dir = scratch.file(name);
  fs::create_directories(dir);
  return dir;
}

// A small "loader": reads track.rail.{mass_kg, n} and the track.model choice, as a real one does.
void readTrack(const Config& c) {
  const auto track = c.section("track");
  const auto rail = track.section("rail");
  rail.number("mass_kg", Range::positive());
  rail.integer("n", 1, 10, 4);
  const std::string model = track.choice("model", {"clm", "winkler"});
  track.section(model).number("k_n_m", Range::positive());
}

}  // namespace

TEST(ConfigStrict, EveryKeyReadIsKnown) {
  const Config c = Config::fromString("track:\n  rail: {mass_kg: 54}\n  model: clm\n  clm: {k_n_m: 1}\n", "t.yaml");
  readTrack(c);
  EXPECT_TRUE(c.unknownKeys().empty());
  EXPECT_NO_THROW(c.refuseUnknownKeys());
}

TEST(ConfigStrict, TypoIsRefusedWithTheNearestKeyAndTheFile) {
  const Config c =
      Config::fromString("track:\n  rail: {mass_kg: 54, mass_kgg: 55}\n  model: clm\n  clm: {k_n_m: 1}\n", "t.yaml");
  readTrack(c);
  expectContains(errorOf([&] { c.refuseUnknownKeys(); }),
                 {"track.rail.mass_kgg = 55", "unknown key", "did you mean track.rail.mass_kg?", "t.yaml"});
}

TEST(ConfigStrict, AnOptionalKeyNotSetIsStillAValidSuggestion) {
  // `n` has a default and is absent: a misspelt `nn` is still pointed at it.
  const Config c = Config::fromString("track:\n  rail: {mass_kg: 54, nn: 3}\n  model: clm\n  clm: {k_n_m: 1}\n");
  readTrack(c);
  expectContains(errorOf([&] { c.refuseUnknownKeys(); }), {"track.rail.nn", "did you mean track.rail.n?"});
}

TEST(ConfigStrict, UnknownSectionIsRefusedOnceAndFarKeysListTheValidOnes) {
  const Config c =
      Config::fromString("trak: {a: 1}\ntrack:\n  rail: {mass_kg: 54, zzzzzzzz: 1}\n  model: clm\n  clm: {k_n_m: 1}\n");
  readTrack(c);
  const auto lines = c.unknownKeys();
  ASSERT_EQ(lines.size(), 2u);
  const std::string all = lines[0] + "\n" + lines[1];
  expectContains(all, {"trak = {a: 1}", "did you mean track?", "track.rail.zzzzzzzz", "valid keys here: mass_kg, n"});
  EXPECT_EQ(all.find("trak.a"), std::string::npos) << "an unknown section is reported once, not per key";
}

TEST(ConfigStrict, TheAlternativeNotChosenIsKnownNotRead) {
  // model: clm; the winkler section stays in the file for when the model is switched.
  const Config c = Config::fromString(
      "track:\n  rail: {mass_kg: 54}\n  model: clm\n  clm: {k_n_m: 1}\n  winkler: {anything: 2}\n  winklr: {x: 1}\n");
  readTrack(c);
  const auto lines = c.unknownKeys();
  ASSERT_EQ(lines.size(), 1u);
  expectContains(lines[0], {"track.winklr", "did you mean track.winkler?"});
}

// An alternative not chosen that its loader validates anyway (soil.boundary keeps every method's
// section and checks them all) is checked key by key: a typo there is refused like anywhere else.
TEST(ConfigStrict, AnAlternativeReadAnywayIsCheckedForTypos) {
  const Config c = Config::fromString(
      "track:\n  rail: {mass_kg: 54}\n  model: clm\n  clm: {k_n_m: 1}\n  winkler: {k_n_m: 2, k_n_mm: 3}\n");
  readTrack(c);
  c.section("track").section("winkler").number("k_n_m", Range::positive());
  const auto lines = c.unknownKeys();
  ASSERT_EQ(lines.size(), 1u);
  expectContains(lines[0], {"track.winkler.k_n_mm", "did you mean track.winkler.k_n_m?"});
}

TEST(ConfigStrict, ListEntriesShareTheirKeys) {
  const Config c = Config::fromString("layers:\n  - {thickness_m: 1}\n  - {thickness_m: 2, thicknes_m: 3}\n");
  for (const auto& l : c.root().sectionList("layers")) l.number("thickness_m", Range::positive());
  expectContains(errorOf([&] { c.refuseUnknownKeys(); }),
                 {"layers[1].thicknes_m", "did you mean layers[1].thickness_m?"});
}

TEST(ConfigStrict, OverrideTyposAreRefusedNamingTheOverride) {
  const fs::path dir = tempDir("override");
  const fs::path f = writeFile(dir, "s.yaml", "track:\n  rail: {mass_kg: 54}\n  model: clm\n  clm: {k_n_m: 1}\n");
  const Config c = Config::load(f.string(), {"track.rail.mas_kg=3"});
  readTrack(c);
  expectContains(errorOf([&] { c.refuseUnknownKeys(); }),
                 {"track.rail.mas_kg = 3", "did you mean track.rail.mass_kg?", "command-line override"});
  fs::remove_all(dir);
}

TEST(ConfigStrict, DuplicateKeysAreRefusedWithBothLines) {
  expectContains(errorOf([] { Config::fromString("a:\n  b: 1\n  c: 2\n  b: 3\n", "dup.yaml"); }),
                 {"dup.yaml:4", "duplicate key 'a.b'", "first set at line 2"});
  expectContains(errorOf([] { Config::fromString("a: {b: 1, b: 2}\n", "flow.yaml"); }), {"duplicate key 'a.b'"});
  expectContains(errorOf([] { Config::fromString("x: 1\nx: 1\n", "top.yaml"); }), {"duplicate key 'x'"});
  // The same key in two entries of a list is no duplicate.
  EXPECT_NO_THROW(Config::fromString("l:\n  - {n: 1}\n  - {n: 2}\n"));
}

TEST(ConfigStrict, DuplicateKeysInAnIncludedFileNameThatFile) {
  const fs::path dir = tempDir("dupinc");
  writeFile(dir, "base.yaml", "track:\n  a_m: 1\n  a_m: 2\n");
  const fs::path top = writeFile(dir, "top.yaml", "include: [base.yaml]\n");
  expectContains(errorOf([&] { Config::load(top.string()); }), {"base.yaml:3", "duplicate key 'track.a_m'"});
  fs::remove_all(dir);
}

TEST(ConfigStrict, AliasBombIsRefusedBeforeItIsExpanded) {
  // Billion laughs: each level nine aliases of the previous one.
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n";
  std::string prev = "a";
  for (char level = 'b'; level <= 'j'; ++level) {
    const std::string name(1, level);
    bomb += name + ": &" + name + " [";
    for (int i = 0; i < 9; ++i) bomb += (i ? ", *" : "*") + prev;
    bomb += "]\n";
    prev = name;
  }
  expectContains(errorOf([&] { Config::fromString(bomb, "bomb.yaml"); }), {"bomb.yaml", "aliases nested"});
  // Wide instead of deep: one anchor, many aliases of it, each one level deep: the size limit.
  std::string wide = "a: &a [";
  for (int i = 0; i < 1000; ++i) wide += (i ? ", " : "") + std::to_string(i);
  wide += "]\nb: [";
  for (int i = 0; i < 200; ++i) wide += (i ? ", *a" : "*a");
  wide += "]\n";
  expectContains(errorOf([&] { Config::fromString(wide, "wide.yaml"); }),
                 {"wide.yaml", "once its aliases are expanded"});
  // A plain alias of a value is fine.
  EXPECT_NO_THROW(Config::fromString("a: &v 3\nb: *v\n"));
}

// An alias inside the value its own anchor names makes a value that contains itself: walking it never
// ends (it crashed the loader on the stack). Refused where the alias stands, in a map and in a list.
TEST(ConfigStrict, AValueThatContainsItselfIsRefused) {
  expectContains(errorOf([] { Config::fromString("track: &t\n  sleeper: *t\n", "cycle.yaml"); }),
                 {"cycle.yaml:2", "would contain itself"});
  expectContains(errorOf([] { Config::fromString("a: &a [1, [2, *a]]\n", "cycle.yaml"); }),
                 {"cycle.yaml:1", "would contain itself"});
  // After its anchor's value has ended, the same alias is an ordinary copy.
  EXPECT_NO_THROW(Config::fromString("a: &a {x: 1}\nb: {y: *a}\n"));
}

// An alias is a copy of its anchor's value, not the same node: an override of one key path changes
// that key only, inside a section and across sections (yaml-cpp's shared node changed both).
TEST(ConfigStrict, AnOverrideOfAnAliasedValueChangesOnlyItsKey) {
  const fs::path dir = tempDir("aliased");
  const fs::path file = writeFile(dir, "aliased.yaml", "a: &v {x: 1, y: 2}\nb: *v\nc:\n  d: &w {x: 1}\n  e: *w\n");
  const Config config = Config::load(file.string(), {"a.x=5", "c.d.x=7"});
  const YAML::Node tree = YAML::Load(config.dump());
  EXPECT_EQ(tree["a"]["x"].as<int>(), 5);
  EXPECT_EQ(tree["b"]["x"].as<int>(), 1);
  EXPECT_EQ(tree["c"]["d"]["x"].as<int>(), 7);
  EXPECT_EQ(tree["c"]["e"]["x"].as<int>(), 1);
  EXPECT_EQ(config.dump().find('&'), std::string::npos) << config.dump();
  fs::remove_all(dir);
}

// The loader reads a text in one pass (its checks and its tree together): the tree is the one
// yaml-cpp's own YAML::Load builds, written the same (values, key order, styles), for every shipped
// config file and texts with what those lack (Config::fromString keeps the tree of its one text as
// it is); an alias is its anchor's value written out.
TEST(ConfigStrict, TheOnePassTreeIsYamlCppsTree) {
  const auto yamlCppTree = [](const std::string& text) {
    YAML::Emitter out;
    out << YAML::Load(text);
    return std::string(out.c_str());
  };
  // With aliases: the same tree as the text with each alias replaced by its anchor's value.
  const std::vector<std::pair<std::string, std::string>> aliased = {
      {"a: &v 3\nb: *v\nc: [*v, {d: *v}]\n", "a: 3\nb: 3\nc: [3, {d: 3}]\n"},
      {"a: &m {x: 1, y: [1, 2]}\nb: *m\nc:\n  - *m\n  - e: ~\n",
       "a: {x: 1, y: [1, 2]}\nb: {x: 1, y: [1, 2]}\nc:\n  - {x: 1, y: [1, 2]}\n  - e: ~\n"},
      {"a: &q 'text'\nb: [*q]\n", "a: 'text'\nb: ['text']\n"},
  };
  for (const auto& [text, written_out] : aliased) {
    EXPECT_EQ(Config::fromString(text).dump(), yamlCppTree(written_out)) << text;
  }
  std::vector<std::string> texts = {
      "a: {e: ~, f:, g: null}\n",
      "a: 'quoted'\nb: \"double\"\nc: !!str 3\nd: !custom x\ne: |\n  block\n  text\nf: >\n  folded\n",
      "flow: {a: [1, {b: 2}], c: []}\nblock:\n  - [1, 2]\n  - {}\nempty_list: []\nn: -1.5e-3\n",
      "z: 1\ny: 2\nx: {c: 3, b: 2, a: 1}\n",
  };
  int files = 0;
  for (const auto& entry : fs::directory_iterator(std::string(RAILVIB_SOURCE_DIR) + "/config")) {
    // (mitigation.yaml is the measures of ./railvib mitigate, whose keys are --set paths: not a Config.)
    if (entry.path().extension() != ".yaml" || entry.path().filename() == "mitigation.yaml") continue;
    std::ifstream in(entry.path());
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // An include is resolved by Config::load, not here: the file's own keys.
    YAML::Node own = YAML::Load(text);
    if (own["include"]) {
      own.remove("include");
      YAML::Emitter out;
      out << own;
      text = out.c_str();
    }
    texts.push_back(text);
    ++files;
  }
  ASSERT_GE(files, 8);
  for (const std::string& text : texts) {
    EXPECT_EQ(Config::fromString(text).dump(), yamlCppTree(text)) << text.substr(0, 200);
  }
}

TEST(ConfigStrict, OversizedDeepAndMultiDocumentFilesAreRefused) {
  const fs::path dir = tempDir("size");
  std::string big = "a:\n";
  while (big.size() <= railvib::kMaxConfigBytes) big += "  # padding padding padding padding padding padding\n";
  const fs::path f = writeFile(dir, "big.yaml", big);
  expectContains(errorOf([&] { Config::load(f.string()); }), {"big.yaml", "bytes, more than"});
  std::string deep = "a: " + std::string(100, '[') + std::string(100, ']') + "\n";
  expectContains(errorOf([&] { Config::fromString(deep, "deep.yaml"); }), {"deep.yaml", "nested deeper than"});
  expectContains(errorOf([&] { Config::fromString("a: 1\n---\nb: 2\n", "two.yaml"); }),
                 {"more than one YAML document"});
  expectContains(errorOf([&] { Config::fromString("? [a, b]\n: 1\n", "key.yaml"); }), {"a key must be a plain name"});
  fs::remove_all(dir);
}

TEST(ConfigStrict, PathsThatAreNoConfigFileAreRefusedByName) {
  const fs::path dir = tempDir("paths");
  expectContains(errorOf([&] { Config::load(dir.string()); }), {dir.string(), "is a directory, not a config file"});
  expectContains(errorOf([&] { Config::load((dir / "missing.yaml").string()); }), {"missing.yaml", "not found"});
  expectContains(errorOf([&] { Config::load("/dev/null"); }), {"/dev/null", "not a regular file"});
  const fs::path inc = writeFile(dir, "inc.yaml", "include: [{a: 1}]\n");
  expectContains(errorOf([&] { Config::load(inc.string()); }), {"inc.yaml", "include entry", "file name"});
  fs::remove_all(dir);
}

TEST(ConfigStrict, OverrideValuesGetTheSameChecks) {
  const fs::path dir = tempDir("ovr");
  const fs::path f = writeFile(dir, "s.yaml", "a: 1\n");
  expectContains(errorOf([&] { Config::load(f.string(), {"a={x: 1, x: 2}"}); }), {"override", "duplicate key"});
  expectContains(errorOf([&] { Config::load(f.string(), {"a=[unclosed"}); }), {"override", "not valid YAML"});
  fs::remove_all(dir);
}

// Include chains: a file included twice (a diamond or a repeat) names both includers; chains deeper
// than 8 files or more than 64 files in all are refused, generated here, whatever the file names.
TEST(ConfigStrict, IncludeChainsAreBoundedAndEachFileIsReadOnce) {
  const fs::path dir = tempDir("inc");
  writeFile(dir, "common.yaml", "track:\n  a_m: 1\n");
  writeFile(dir, "site.yaml", "include: [common.yaml]\n");
  writeFile(dir, "vehicle.yaml", "include: [common.yaml]\n");
  const fs::path diamond = writeFile(dir, "diamond.yaml", "include: [site.yaml, vehicle.yaml]\n");
  expectContains(errorOf([&] { Config::load(diamond.string()); }),
                 {"vehicle.yaml", "include", "common.yaml", "already included (by", "site.yaml"});
  const fs::path twice = writeFile(dir, "twice.yaml", "include: [common.yaml, common.yaml]\n");
  expectContains(errorOf([&] { Config::load(twice.string()); }), {"twice.yaml", "already included"});
  for (const size_t depth : {7u, 8u, 9u, 20u}) {
    // chain_0 includes chain_1 ... includes chain_{depth-1}: depth files in all.
    for (size_t i = 0; i < depth; ++i) {
      writeFile(dir, "chain_" + std::to_string(i) + ".yaml",
                i + 1 < depth ? "include: [chain_" + std::to_string(i + 1) + ".yaml]\n" : "track:\n  a_m: 1\n");
    }
    const std::string top = (dir / "chain_0.yaml").string();
    if (depth <= 8) {
      EXPECT_EQ(Config::load(top).section("track").number("a_m", Range::any()), 1.0) << depth;
    } else {
      expectContains(errorOf([&] { Config::load(top); }), {"more than 8 files deep"});
    }
  }
  for (const size_t count : {64u, 65u, 500u}) {
    // One file including count - 1 distinct files (count files in all).
    std::string list = "include: [";
    for (size_t i = 1; i < count; ++i) {
      writeFile(dir, "leaf_" + std::to_string(i) + ".yaml", "leaf_" + std::to_string(i) + ": 1\n");
      list += (i > 1 ? ", leaf_" : "leaf_") + std::to_string(i) + ".yaml";
    }
    const fs::path wide = writeFile(dir, "wide.yaml", list + "]\n");
    if (count <= 64) {
      EXPECT_NO_THROW(Config::load(wide.string())) << count;
    } else {
      expectContains(errorOf([&] { Config::load(wide.string()); }), {"wide.yaml", "more than 64 files"});
    }
  }
  fs::remove_all(dir);
}

// A key path written as one key, at the top or inside a section, is refused with how to write it.
TEST(ConfigStrict, DottedKeysAreRefusedWithTheNestedForm) {
  for (const std::string& text :
       {std::string("soil.mesh.f_max_hz: 30\n"), std::string("soil:\n  mesh.f_max_hz: 30\n")}) {
    expectContains(errorOf([&] { Config::fromString(text, "dots.yaml"); }),
                   {"dots.yaml", "'soil.mesh.f_max_hz' holds dots", "--set soil.mesh.f_max_hz=VALUE"});
  }
}

// Numbers written as text: every number getter refuses a quoted or !!str-tagged scalar, and takes the
// same value written plain, in any of YAML's number forms.
TEST(ConfigStrict, NumbersWrittenAsTextAreRefused) {
  for (const std::string text : {"'8.0e6'", "\"8.0e6\"", "!!str 8.0e6", "'3'"}) {
    const Config c = Config::fromString("a:\n  x: " + text + "\n  l: [1, " + text + "]\n", "q.yaml");
    const auto a = c.section("a");
    expectContains(errorOf([&] { a.number("x", Range::any()); }), {"a.x", "is text (in quotes or tagged !!str)"});
    expectContains(errorOf([&] { a.integer("x", 0, 10000000000L); }), {"a.x", "is text"});
    expectContains(errorOf([&] { a.numbers("l", Range::any()); }), {"a.l", "is text"});
  }
  for (const std::string text : {"8.0e6", "8e6", "8000000", "8.0e+6", "!!float 8.0e6"}) {
    const Config c = Config::fromString("a:\n  x: " + text + "\n", "plain.yaml");
    EXPECT_EQ(c.section("a").number("x", Range::any()), 8.0e6) << text;
  }
}

// An override reaches one entry of a list by its index (soil.layers[1].thickness_m=20), as the error
// messages name it; the other entries stay as the files have them. An index names an entry that exists.
TEST(ConfigStrict, AnOverrideReachesOneListEntryByItsIndex) {
  const fs::path dir = tempDir("index");
  const fs::path f = writeFile(dir, "s.yaml",
                               "layers:\n  - {name: top, thickness_m: 1}\n  - {name: deep, thickness_m: 2}\n"
                               "grid: [[1, 2], [3, 4]]\nrail: {mass_kg: 54}\n");
  const Config c = Config::load(f.string(), {"layers[1].thickness_m=5", "grid[1][0]=7"});
  const auto layers = c.root().sectionList("layers");
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_DOUBLE_EQ(layers[0].number("thickness_m", Range::positive()), 1.0);
  EXPECT_DOUBLE_EQ(layers[1].number("thickness_m", Range::positive()), 5.0);
  EXPECT_EQ(layers[1].text("name"), "deep");  // the entry's other keys stay
  const YAML::Node grid = c.root().yaml()["grid"];
  ASSERT_TRUE(grid.IsSequence());
  EXPECT_EQ(grid[1][0].as<int>(), 7);  // one index per list level
  EXPECT_EQ(grid[1][1].as<int>(), 4);
  EXPECT_EQ(grid[0][0].as<int>(), 1);

  // A map merges into the entry as into any section; the value is checked with the override named.
  const Config merged = Config::load(f.string(), {"layers[0]={thickness_m: -3}"});
  const auto top = merged.root().sectionList("layers")[0];
  EXPECT_EQ(top.text("name"), "top");
  expectContains(errorOf([&] { top.number("thickness_m", Range::positive()); }),
                 {"layers[0].thickness_m", "-3", "command-line override 'layers[0]={thickness_m: -3}'"});
  // A typo inside an entry is an unknown key of that entry.
  const Config typo = Config::load(f.string(), {"layers[1].thicknes_m=3"});
  for (const auto& l : typo.root().sectionList("layers")) {
    l.text("name");
    l.number("thickness_m", Range::positive());
  }
  typo.root().section("rail").number("mass_kg", Range::positive());
  expectContains(errorOf([&] { typo.refuseUnknownKeys(); }),
                 {"layers[1].thicknes_m", "did you mean layers[1].thickness_m?", "command-line override"});

  // Entries that do not exist, keys that are no lists, indices that are no positions.
  expectContains(errorOf([&] { Config::load(f.string(), {"layers[2].thickness_m=5"}); }),
                 {"layers[2].thickness_m=5", "layers has 2 entries (indices 0 to 1), no [2]", "layers=[...]"});
  expectContains(errorOf([&] { Config::load(f.string(), {"grid[0][2]=5"}); }), {"grid[0] has 2 entries", "no [2]"});
  expectContains(errorOf([&] { Config::load(f.string(), {"rail[0].mass_kg=5"}); }), {"rail is not a list"});
  expectContains(errorOf([&] { Config::load(f.string(), {"tracks[0].mass_kg=5"}); }), {"tracks is not set"});
  for (const char* bad : {"layers[x].thickness_m=1", "layers[-1].thickness_m=1", "layers[].thickness_m=1",
                          "layers[99999999].thickness_m=1", "layers[1.thickness_m=1", "layers]1[.thickness_m=1",
                          "[1].thickness_m=1", "layers[1]x.thickness_m=1", "layers..thickness_m=1", "layers[1].=1"}) {
    const std::string message = errorOf([&] { Config::load(f.string(), {bad}); });
    expectContains(message, {std::string("override '") + bad + "'", "key.key[INDEX].key"});
  }
  fs::remove_all(dir);
}
