// The whole-scenario check (scenario::validateScenario) and a property fuzz of every key of the
// CI scenario: each numeric value replaced by NaN, inf, 1e300 or text, each value by a map or a
// list, each key misspelt or repeated, is refused with a ConfigError naming the key; no other
// exception escapes. Run under AddressSanitizer and UndefinedBehaviorSanitizer too.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"
#include "railvib/common/machine.hpp"
#include "railvib/common/plausibility.hpp"
#include "railvib/scenario/launch_arguments.hpp"
#include "railvib/scenario/scenario.hpp"
#include "test_sampling.hpp"
#include "test_scratch.hpp"

namespace fs = std::filesystem;
using railvib::Config;
using railvib::ConfigError;
using railvib::scenario::validateScenario;

namespace {

std::string configPath(const std::string& name) { return std::string(RAILVIB_SOURCE_DIR) + "/config/" + name; }

fs::path tempDir() {
  static const railvib::test::ScratchDir scratch("scenario");
  return scratch.path();
}

// "" when the scenario is valid, else the ConfigError's message; any other exception fails the test.
std::string verdict(const std::function<Config()>& load) {
  try {
    validateScenario(load());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string verdictOfText(const std::string& yaml) {
  const fs::path file = tempDir() / "mutated.yaml";
  std::ofstream(file) << yaml;
  return verdict([&] { return Config::load(file.string()); });
}

std::string verdictOf(const std::string& file, const std::vector<std::string>& overrides) {
  return verdict([&] { return Config::load(configPath(file), overrides); });
}

// A leaf of the merged tree: its key path (with list indices) and the YAML path to it.
struct Leaf {
  std::string path;
  std::vector<std::string> keys;  // a number string stands for a list index
  std::vector<bool> is_index;
  YAML::Node value;
};

void collect(const YAML::Node& node, Leaf prefix, std::vector<Leaf>& out, bool maps_too) {
  if (node.IsMap()) {
    if (maps_too && !prefix.path.empty()) {
      Leaf self = prefix;
      self.value = node;
      out.push_back(self);
    }
    for (const auto& kv : node) {
      Leaf child = prefix;
      const std::string k = kv.first.as<std::string>();
      child.path = prefix.path.empty() ? k : prefix.path + "." + k;
      child.keys.push_back(k);
      child.is_index.push_back(false);
      collect(kv.second, child, out, maps_too);
    }
  } else if (node.IsSequence() && node.size() > 0 && node[0].IsMap()) {
    for (size_t i = 0; i < node.size(); ++i) {
      Leaf child = prefix;
      child.path += "[" + std::to_string(i) + "]";
      child.keys.push_back(std::to_string(i));
      child.is_index.push_back(true);
      collect(node[i], child, out, maps_too);
    }
  } else {
    prefix.value = node;
    out.push_back(prefix);
  }
}

// The node `depth` keys down the leaf's path. By recursion on copies: assigning one yaml-cpp node
// to another would rebind the tree's nodes instead of moving a handle.
YAML::Node at(YAML::Node n, const Leaf& leaf, size_t depth, size_t i = 0) {
  if (i == depth) return n;
  return at(leaf.is_index[i] ? n[std::stoul(leaf.keys[i])] : n[leaf.keys[i]], leaf, depth, i + 1);
}

std::string emit(const YAML::Node& root) {
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

// The merged CI scenario as one YAML tree (includes resolved).
YAML::Node ciTree() { return YAML::Load(Config::load(configPath("haren_ci.yaml")).dump()); }

bool isNumber(const YAML::Node& v) {
  if (!v.IsScalar()) return false;
  const std::string s = v.Scalar();
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size();
}

// The alternative the CI scenario does not choose (soil.boundary.method: dashpots): known, not read.
bool inactive(const std::string& path) { return path.rfind("soil.boundary.graded_layer", 0) == 0; }

}  // namespace

TEST(Scenario, TheShippedScenariosAreValid) {
  for (const char* file : {"haren.yaml", "haren_ci.yaml"}) {
    nlohmann::json summary;
    ASSERT_NO_THROW(summary = validateScenario(Config::load(configPath(file)))) << file;
    EXPECT_TRUE(summary["valid"].get<bool>());
    ASSERT_EQ(summary["virtual_sensors"].size(), 4u);
    EXPECT_EQ(summary["virtual_sensors"][0]["name"], "ground_2m");
    EXPECT_DOUBLE_EQ(summary["rates_hz"]["soil_loads"].get<double>(), 2000.0);
  }
}

// With two-way coupling the foundation is part of the soil: a ground sensor inside the house's plan
// (Haren's 8 m point: the house spans y 4.7175..11.7175 m in front of the defect) records the
// foundation, and the scenario says so; on the plan's edge it still does, 1 cm off it it does not.
TEST(Scenario, GroundSensorsOnTheTwoWayFoundationAreNamed) {
  auto notes = [](std::vector<std::string> overrides) {
    return validateScenario(Config::load(configPath("haren.yaml"), overrides))["notes"];
  };
  const nlohmann::json two_way = notes({"building.foundation.model=rigid"});
  ASSERT_EQ(two_way.size(), 1u) << two_way.dump();
  const std::string note = two_way[0].get<std::string>();
  EXPECT_EQ(note.rfind("sensor ground_8m at (0, 8) m stands on the house's foundation", 0), 0u) << note;
  EXPECT_NE(note.find("coupling one_way"), std::string::npos) << note;
  EXPECT_NE(note.find("foundation's rigid motion"), std::string::npos) << note;
  // A meshed foundation's ground slab bends: the note does not call its motion rigid.
  const nlohmann::json meshed = notes({});  // the default box: meshed in concrete
  ASSERT_EQ(meshed.size(), 1u) << meshed.dump();
  EXPECT_NE(meshed[0].get<std::string>().find("meshed foundation's motion"), std::string::npos) << meshed.dump();
  EXPECT_TRUE(notes({"building.coupling=one_way"}).empty());
  // The 8 m sensor placed at (x, y) m, the other sensors as in the file.
  const auto placed = [](const std::string& x, const std::string& y) {
    return "virtual_sensors.sensors=[{name: ground_2m, kind: free_field, x_m: 0.0, y_m: 2.0}, "
           "{name: ground_8m, kind: free_field, x_m: " +
           x + ", y_m: " + y +
           "}, "
           "{name: house_ground_floor, kind: foundation, point: ground_floor, x_m: 7.5, y_m: 3.5, z_m: 0.0}, "
           "{name: house_first_floor, kind: floor, point: first_floor, x_m: 7.5, y_m: 3.5, z_m: 2.5}]";
  };
  EXPECT_EQ(notes({placed("5.0", "11.7175")}).size(), 1u);  // the plan's corner
  EXPECT_TRUE(notes({placed("5.01", "8.0")}).empty());
  EXPECT_TRUE(notes({placed("0.0", "4.7075")}).empty());  // 1 cm in front of the front wall
}

// Every case in the regular build; every n-th in the sanitizer run, where one scenario check takes
// ~10 x longer (test_sampling.hpp).
size_t fuzzStride() { return railvib::test::sampleStride(); }

// A plain scalar that no config holds, standing for a leaf's value in the written tree.
const std::string kSlot = "railvib_fuzz_value_slot";

TEST(ScenarioFuzz, EveryValueReplacedByNonsenseIsRefusedByItsKey) {
  const YAML::Node tree = ciTree();
  std::vector<Leaf> leaves;
  collect(tree, Leaf{}, leaves, false);
  ASSERT_GT(leaves.size(), 150u);
  std::vector<std::string> silent;
  size_t cases = 0, seen = 0;
  const size_t stride = fuzzStride();
  for (const Leaf& leaf : leaves) {
    if (inactive(leaf.path)) continue;
    std::vector<std::string> bad{"{bad: 1}"};
    if (!leaf.value.IsSequence()) bad.push_back("[1, 2]");
    if (isNumber(leaf.value)) {
      for (const char* v : {".nan", ".inf", "-.inf", "1.0e+300", "-1.0e+300", "abc"}) bad.push_back(v);
    }
    std::vector<std::string> chosen;
    for (const std::string& b : bad) {
      if (seen++ % stride == 0) chosen.push_back(b);
    }
    if (chosen.empty()) continue;
    // The tree is cloned and written once per leaf, with a placeholder at the leaf; each nonsense value
    // is put in its place in the text (each is flow YAML, valid in block and flow context alike).
    YAML::Node copy = YAML::Clone(tree);
    at(copy, leaf, leaf.keys.size() - 1)[leaf.keys.back()] = kSlot;
    const std::string text = emit(copy);
    const size_t slot = text.find(kSlot);
    ASSERT_NE(slot, std::string::npos) << leaf.path;
    ASSERT_EQ(text.find(kSlot, slot + 1), std::string::npos) << leaf.path << ": placeholder written twice";
    for (const std::string& b : chosen) {
      const std::string message = verdictOfText(text.substr(0, slot) + b + text.substr(slot + kSlot.size()));
      ++cases;
      // The key path is named (list entries by their own path, e.g. soil.layers[2].thickness_m).
      if (message.empty()) {
        silent.push_back(leaf.path + " = " + b);
      } else if (message.find(leaf.path) == std::string::npos) {
        ADD_FAILURE() << leaf.path << " = " << b << ": refused without naming the key: " << message;
      }
    }
  }
  EXPECT_GT(cases, 800u / stride);
  std::string list;
  for (const auto& s : silent) list += "\n  " + s;
  EXPECT_TRUE(silent.empty()) << silent.size() << " nonsense values accepted:" << list;
}

TEST(ScenarioFuzz, EveryMisspeltKeyIsRefusedWithTheIntendedOne) {
  const YAML::Node tree = ciTree();
  std::vector<Leaf> nodes;
  collect(tree, Leaf{}, nodes, true);
  size_t cases = 0, seen = 0;
  const size_t stride = fuzzStride();
  for (const Leaf& leaf : nodes) {
    if (leaf.is_index.back() || inactive(leaf.path)) continue;
    if (seen++ % stride != 0) continue;
    const std::string key = leaf.keys.back();
    const std::string typo = key + key.back();  // one letter repeated: the commonest slip
    // A vehicle of the library that the scenario does not select may take any name: renaming it is no typo.
    if (leaf.keys.size() == 2 && leaf.keys[0] == "vehicles" && key != tree["vehicle"]["name"].as<std::string>()) {
      continue;
    }
    YAML::Node copy = YAML::Clone(tree);
    YAML::Node parent = at(copy, leaf, leaf.keys.size() - 1);
    if (parent[typo]) continue;  // collides with a real key
    parent.remove(key);
    parent[typo] = YAML::Clone(leaf.value);
    const std::string message = verdictOfText(emit(copy));
    ++cases;
    const std::string parent_path = leaf.path.substr(0, leaf.path.size() - key.size());
    const bool suggested = message.find("did you mean " + leaf.path + "?") != std::string::npos ||
                           message.find("is '" + parent_path + typo + "' a misspelling") != std::string::npos;
    // Or the refusal names the intended key: a required or defaulted key now missing, which a loader's
    // own check finds first (vehicles.t2000.suspensions[3].y_m = (missing): ...), or a name defined by
    // the file (a vehicle, a body, a suspension stage) that its references no longer find
    // (suspensions[0].upper = front_carbody: no body 'front_carbody' ...).
    const bool named = message.find(leaf.path + " = (missing)") != std::string::npos ||
                       message.find("= " + key + ":") != std::string::npos ||
                       message.find("'" + key + "'") != std::string::npos;
    EXPECT_TRUE(suggested || named) << leaf.path << " misspelt as " << typo << ": " << message;
  }
  EXPECT_GT(cases, 150u / stride);
}

TEST(ScenarioFuzz, EveryRepeatedKeyIsRefused) {
  // Block YAML of the merged tree, one key per line: repeat each line in turn.
  std::istringstream in(emit(ciTree()));
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  size_t cases = 0;
  for (size_t i = 0; i < lines.size(); i += 3) {  // every third line keeps the run short
    const std::string& l = lines[i];
    const size_t colon = l.find(':');
    if (colon == std::string::npos || l.find_first_not_of(" ") == l.find('-')) continue;
    std::string text;
    for (size_t j = 0; j < lines.size(); ++j) text += lines[j] + "\n" + (j == i ? lines[j] + "\n" : "");
    const std::string message = verdictOfText(text);
    ++cases;
    EXPECT_NE(message.find("duplicate key"), std::string::npos) << "line " << i + 1 << " repeated: " << l;
  }
  EXPECT_GT(cases, 30u);
}

TEST(Scenario, CrossChecksBetweenSections) {
  auto expect = [](const std::string& message, const std::vector<std::string>& parts) {
    ASSERT_FALSE(message.empty());
    for (const auto& p : parts) EXPECT_NE(message.find(p), std::string::npos) << p << " not in: " << message;
  };
  expect(verdictOf("haren_ci.yaml", {"track.output.load_sample_rate_hz=200000"}),
         {"track.output.load_sample_rate_hz = 200000", "above the rate of the vehicle/track steps"});
  expect(verdictOf("haren_ci.yaml", {"track.output.load_sample_rate_hz=30"}), {"below twice", "f_max_hz"});
  expect(verdictOf("haren_ci.yaml", {"virtual_sensors.sample_rate_hz=2000"}),
         {"virtual_sensors.sample_rate_hz = 2000", "receiver_rate_hz"});
  expect(verdictOf("haren_ci.yaml", {"virtual_sensors.din4150_2_perod=night"}),
         {"virtual_sensors.din4150_2_perod", "did you mean virtual_sensors.din4150_2_period?"});
  expect(verdictOf("haren_ci.yaml", {"virtual_sensors.sample_rate_hz=-5"}), {"virtual_sensors.sample_rate_hz = -5"});
  expect(verdictOf("haren_ci.yaml", {"unevenness.measured_profile.enabled=true",
                                     "unevenness.measured_profile.file=/nonexistent/profile.csv"}),
         {"unevenness.measured_profile.file", "no such file"});
  // The house in the soil (two-way): refused at config time as the soil node would refuse it.
  expect(
      verdictOf("haren_ci.yaml", {"building.foundation.model=meshed"}),
      {"building.foundation.model = meshed", "too coarse for the foundation box", "building.foundation.model: rigid"});
  expect(verdictOf("haren_ci.yaml", {"site.building.front_wall_distance_from_rail_m=0.3"}),
         {"site.building.front_wall_distance_from_rail_m = 0.3", "overlaps the track"});
  expect(verdictOf("haren_ci.yaml", {"building.coupling_modes_max_hz=30.0"}),
         {"building.coupling_modes_max_hz = 30", "twice the soil's"});
  // One-way: the soil does not hold the house, so nothing of it is checked against the mesh.
  EXPECT_EQ(verdictOf("haren_ci.yaml", {"building.foundation.model=meshed", "building.coupling=one_way"}), "");
}

TEST(Scenario, ASensorAtAPointNoSourceOutputsIsRefused) {
  const YAML::Node tree = ciTree();
  YAML::Node copy = YAML::Clone(tree);
  // A sensor that reads a point defined elsewhere (source and point, no position) names one.
  copy["virtual_sensors"]["sensors"][1] = YAML::Load("{name: ground_8m, source: soil, point: ground_9m}");
  const std::string m = verdictOfText(emit(copy));
  EXPECT_NE(m.find("virtual_sensors.sensors[1].point = ground_9m"), std::string::npos) << m;
  copy = YAML::Clone(tree);
  copy["virtual_sensors"]["sensors"][3] = YAML::Load("{name: house_first_floor, source: building, point: attic}");
  EXPECT_NE(verdictOfText(emit(copy)).find("building response point"), std::string::npos);
  // The same point named by the reference form reads the placed sensor's point: accepted.
  copy = YAML::Clone(tree);
  copy["virtual_sensors"]["sensors"].push_back(YAML::Load("{name: second_8m, source: soil, point: ground_8m}"));
  EXPECT_EQ(verdictOfText(emit(copy)), "");
}

TEST(Scenario, AMeshBeyondTheMachineIsRefusedWhateverMaxMemoryAllows) {
  ASSERT_GT(railvib::machineMemoryBytes(), 1e8);
  // 800 Hz on the production box: ~3.6e9 elements, ~300 GB, more than any machine this runs on; the
  // cap is raised to 9999 GB.
  const std::string m = verdictOf("haren.yaml", {"soil.mesh.max_memory_gb=9999", "soil.mesh.f_max_hz=800"});
  EXPECT_NE(m.find("soil.mesh.max_memory_gb = 9999"), std::string::npos) << m;
  EXPECT_NE(m.find("of memory of this machine"), std::string::npos) << m;
  // Far beyond any machine: refused by counting, before anything is sized.
  const std::string huge =
      verdictOf("haren.yaml", {"soil.mesh.f_max_hz=9000", "soil.mesh.elements_per_wavelength=100"});
  EXPECT_NE(huge.find("soil.mesh.f_max_hz"), std::string::npos) << huge;
  EXPECT_NE(huge.find("any machine could hold"), std::string::npos) << huge;
}

TEST(Scenario, AMeasuredProfileIsReadAndCheckedAtConfigTime) {
  const fs::path dir = tempDir();
  const auto with_profile = [&](const std::string& csv) {
    std::ofstream(dir / "profile.csv") << csv;
    return verdictOf("haren_ci.yaml", {"unevenness.measured_profile.enabled=true",
                                       "unevenness.measured_profile.file=" + (dir / "profile.csv").string()});
  };
  EXPECT_EQ(with_profile("x_m,z_m\n-10,0\n0,1e-4\n10,0\n"), "");
  const std::string nan = with_profile("x_m,z_m\n-10,0\n0,nan\n10,0\n");
  EXPECT_NE(nan.find("unevenness.measured_profile.file"), std::string::npos) << nan;
  EXPECT_NE(nan.find("profile.csv:3"), std::string::npos) << nan;
  EXPECT_NE(with_profile("x_m,z_m\n-10,0\n0,5\n10,0\n").find("limits.unevenness_m"), std::string::npos);
  EXPECT_NE(with_profile("x_m,z_m\n-10,0\n-20,0\n").find("must be greater"), std::string::npos);
  // A profile beside the track (another frame, or x in mm) would be read as no unevenness: refused.
  const std::string beside = with_profile("x_m,z_m\n5000,0\n5010,1e-4\n");
  EXPECT_NE(beside.find("outside the track's"), std::string::npos) << beside;
  EXPECT_NE(beside.find("unevenness.measured_profile.file"), std::string::npos) << beside;
}

// Unit slips, generated over every key of the CI scenario that holds a physical quantity with a
// typical range (railvib/common/plausibility.hpp): its value times each factor a wrong unit gives
// (g/cm^3 for kg/m^3, MN/m for N/m, km/h for m/s, mm for m...) is refused naming the key, the
// typical range and plausibility.accept when it leaves that range; listed under plausibility.accept,
// the same value is no longer refused for being atypical.
TEST(ScenarioFuzz, EveryUnitSlipOutsideTheTypicalRangeIsRefusedUnlessAccepted) {
  const YAML::Node tree = ciTree();
  std::vector<Leaf> leaves;
  collect(tree, Leaf{}, leaves, false);
  size_t slips = 0, accepted = 0, keys = 0, seen = 0;
  const size_t stride = fuzzStride();
  for (const Leaf& leaf : leaves) {
    if (inactive(leaf.path) || !isNumber(leaf.value)) continue;
    const railvib::PlausibilityRule* rule = railvib::plausibilityRuleFor(leaf.path);
    if (!rule) continue;
    const double value = leaf.value.as<double>();
    if (value == 0.0) continue;
    ASSERT_TRUE(railvib::isTypical(*rule, value)) << leaf.path << " = " << value << " in the shipped scenario";
    ++keys;
    // Per key the nearest slip below and above that leaves the typical range (unit factors 1e3 apart,
    // and km/h's 3.6).
    std::vector<double> factors;
    for (const auto& side :
         {std::vector<double>{1.0 / 3.6, 1e-3, 1e-6, 1e-9}, std::vector<double>{3.6, 1e3, 1e6, 1e9}}) {
      for (const double f : side) {
        if (!railvib::isTypical(*rule, value * f)) {
          factors.push_back(f);
          break;
        }
      }
    }
    for (const double factor : factors) {
      const double slipped = value * factor;
      if (seen++ % stride != 0) continue;
      std::ostringstream text;
      text.precision(17);
      text << slipped;
      YAML::Node copy = YAML::Clone(tree);
      at(copy, leaf, leaf.keys.size() - 1)[leaf.keys.back()] = YAML::Load(text.str());
      const std::string message = verdictOfText(emit(copy));
      ++slips;
      EXPECT_NE(message.find(leaf.path), std::string::npos) << leaf.path << " = " << slipped << ": " << message;
      // Refused by its own allowed range first, or else as atypical, with the way out.
      if (message.find("typical range") != std::string::npos) {
        EXPECT_NE(message.find("plausibility.accept"), std::string::npos) << message;
        copy["plausibility"]["accept"].push_back(leaf.path);
        const std::string again = verdictOfText(emit(copy));
        EXPECT_EQ(again.find(leaf.path + " = " + text.str() + ": outside the typical range"), std::string::npos)
            << "accepted, still refused as atypical: " << again;
        ++accepted;
      } else {  // its allowed range, or the magnitude no scenario value reaches
        EXPECT_TRUE(message.find("range") != std::string::npos || message.find("magnitude") != std::string::npos)
            << leaf.path << " = " << slipped << ": " << message;
      }
    }
  }
  std::printf("unit slips: %zu keys with a typical range, %zu slipped values refused, %zu of them as atypical\n", keys,
              slips, accepted);
  EXPECT_GT(keys, 30u);
  EXPECT_GT(slips, 60u / stride);
  EXPECT_GT(accepted, 30u / stride);
}

// Each launch argument sets its one config key and nothing else (the nodes' map, and config-check --arg's):
// a value that would add a key or a list is refused naming the argument; an empty one keeps the file's value.
TEST(LaunchArguments, EachSetsItsOneKeyWithOnePlainValue) {
  using railvib::scenario::launchArgumentKeys;
  using railvib::scenario::launchArgumentOverrides;
  const std::vector<std::string> set =
      launchArgumentOverrides({{"speed", "5"}, {"duration", ""}, {"coupling", "one_way"}});
  EXPECT_EQ(set, (std::vector<std::string>{"simulation.speed_m_s=5", "building.coupling=one_way"}));
  // Every mapped key is one the CI scenario holds, and a launch of it with that key's own value is valid.
  const Config ci = Config::load(configPath("haren_ci.yaml"));
  const YAML::Node tree = YAML::Load(ci.dump());
  for (const auto& [name, key] : launchArgumentKeys()) {
    YAML::Node node = YAML::Clone(tree);
    std::stringstream path(key);
    for (std::string step; std::getline(path, step, '.');)
      node.reset(node[step]);  // not =: it would assign into the tree
    ASSERT_TRUE(node.IsScalar()) << name << " -> " << key;
    const std::vector<std::string> one = launchArgumentOverrides({{name, node.Scalar()}});
    ASSERT_EQ(one, (std::vector<std::string>{key + "=" + node.Scalar()}));
    EXPECT_NO_THROW(validateScenario(Config::load(configPath("haren_ci.yaml"), one))) << name;
  }
  auto refused = [](const std::string& name, const std::string& value) {
    try {
      launchArgumentOverrides({{name, value}});
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused("sped", "5").find("not one the nodes know (speed, duration"), std::string::npos);
  for (const char* injection : {"5\", \"soil.mesh.max_memory_gb=9999", "5, soil.mesh.max_memory_gb=9999", "[1, 2]",
                                "{a: 1}", "5\nsoil: {}", "a: b"}) {
    EXPECT_NE(refused("speed", injection).find("launch argument speed:= must be one plain value"), std::string::npos)
        << injection;
  }
}

TEST(ScenarioFuzz, PlausibilityAcceptIsAListOfKeyPaths) {
  for (const char* bad : {"plausibility=3", "plausibility={accept: 3}", "plausibility={accept: [{a: 1}]}",
                          "plausibility={allow: [simulation.speed_m_s]}"}) {
    const std::string message = verdictOf("haren_ci.yaml", {bad});
    EXPECT_NE(message.find("plausibility"), std::string::npos) << bad << ": " << message;
  }
  EXPECT_EQ(verdictOf("haren_ci.yaml", {"plausibility={accept: [simulation.speed_m_s]}"}), "");
}

// A --set that replaces a list by a shorter one drops entries the files had: the scenario's notes say
// which, by name; the same list with every entry says nothing.
TEST(Scenario, AnOverrideThatDropsListEntriesIsNamedInTheNotes) {
  const YAML::Node sensors = ciTree()["virtual_sensors"]["sensors"];
  ASSERT_GE(sensors.size(), 2u);
  const auto flow = [](const YAML::Node& n) {
    YAML::Emitter out;
    out << YAML::Flow << n;
    return std::string(out.c_str());
  };
  YAML::Node first(YAML::NodeType::Sequence);
  first.push_back(sensors[0]);
  const nlohmann::json notes =
      validateScenario(Config::load(configPath("haren_ci.yaml"), {"virtual_sensors.sensors=" + flow(first)}))["notes"];
  std::string dropped;
  for (size_t i = 1; i < sensors.size(); ++i) dropped += (i > 1 ? ", " : "") + sensors[i]["name"].as<std::string>();
  bool found = false;
  for (const auto& n : notes) {
    const std::string note = n.get<std::string>();
    if (note.find("virtual_sensors.sensors") == std::string::npos) continue;
    found = true;
    EXPECT_NE(note.find("replaces a list of " + std::to_string(sensors.size()) + " entries by 1"), std::string::npos)
        << note;
    EXPECT_NE(note.find("dropped: " + dropped), std::string::npos) << note;
  }
  EXPECT_TRUE(found) << notes.dump();
  const nlohmann::json same = validateScenario(
      Config::load(configPath("haren_ci.yaml"), {"virtual_sensors.sensors=" + flow(sensors)}))["notes"];
  for (const auto& n : same) EXPECT_EQ(n.get<std::string>().find("virtual_sensors.sensors"), std::string::npos);
}
