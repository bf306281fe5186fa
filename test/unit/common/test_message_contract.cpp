// The contract of the non-stream messages (metrics, snapshots, transforms) that every reader applies
// before it uses or records one: every case of test/data/message_contract_cases.json (the table the
// Python readers are held to as well) is refused naming its field, or accepted when valid; and a
// mutation fuzz of valid snapshots never reads out of bounds (run under the sanitizers too).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "railvib/common/message_contract.hpp"

namespace {

using nlohmann::json;

json loadTable() {
  std::ifstream in(std::string(RAILVIB_SOURCE_DIR) + "/test/data/message_contract_cases.json");
  EXPECT_TRUE(in.good());
  return json::parse(in);
}

// Numbers, or the strings nan / inf / -inf for the values JSON cannot write.
double number(const json& v) {
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    ADD_FAILURE() << "not a number: " << s;
    return 0.0;
  }
  return v.get<double>();
}

// A list, or "N bands" / "N levels" (N band centres 1.0 * 10^(k/10) Hz, or N levels of 60 dB).
std::vector<double> numbers(const json& v) {
  std::vector<double> out;
  if (v.is_string()) {
    std::smatch m;
    const std::string s = v.get<std::string>();
    EXPECT_TRUE(std::regex_match(s, m, std::regex("([0-9]+) (bands|levels)"))) << s;
    const int n = std::stoi(m[1]);
    for (int k = 0; k < n; ++k) out.push_back(m[2] == "bands" ? std::pow(10.0, k / 10.0) : 60.0);
    return out;
  }
  for (const auto& x : v) out.push_back(number(x));
  return out;
}

std::vector<float> floats(const json& v) {
  std::vector<float> out;
  for (double x : numbers(v)) out.push_back(static_cast<float>(x));
  return out;
}

// The refusal of one case ("" when accepted).
std::string verdictOf(const std::string& kind, const json& m, const railvib::StreamLimits& limits,
                      const std::vector<std::string>& sensors) {
  try {
    if (kind == "metrics") {
      railvib::MetricsFields f;
      const std::vector<double> centres = numbers(m["third_octave_center_hz"]);
      const std::vector<double> levels = numbers(m["third_octave_level_db"]);
      f.sensor_name = m["sensor_name"].get<std::string>();
      f.kind = m["kind"].get<uint32_t>();
      f.resolved_hz = number(m["resolved_hz"]);
      f.kb_f = number(m["kb_f"]);
      f.kb_f_max = number(m["kb_f_max"]);
      f.ppv_m_s = number(m["ppv_m_s"]);
      f.ppv_vertical_m_s = number(m["ppv_vertical_m_s"]);
      f.governing_component = m["governing_component"].get<uint32_t>();
      f.governing_ppv_m_s = number(m["governing_ppv_m_s"]);
      f.dominant_frequency_hz = number(m["dominant_frequency_hz"]);
      f.din4150_3_limit_m_s = number(m["din4150_3_limit_m_s"]);
      f.third_octave_center_hz = &centres;
      f.third_octave_level_db = &levels;
      f.din4150_2_verdict = m["din4150_2_verdict"].get<uint32_t>();
      f.din4150_2_a_u = number(m["din4150_2_a_u"]);
      f.din4150_2_a_o = number(m["din4150_2_a_o"]);
      f.din4150_2_a_r = number(m["din4150_2_a_r"]);
      f.din4150_3_verdict = m["din4150_3_verdict"].get<uint32_t>();
      f.verdict = m["verdict"].get<uint32_t>();
      railvib::validateMetrics("/sensor_metrics", f, limits, sensors);
    } else if (kind == "surface" || kind == "section") {
      // The horizontal fields are optional in the table (absent: empty, as a vertical-only snapshot).
      const std::vector<float> vx = m.contains("velocity_x_m_s") ? floats(m["velocity_x_m_s"]) : std::vector<float>{};
      const std::vector<float> vy = m.contains("velocity_y_m_s") ? floats(m["velocity_y_m_s"]) : std::vector<float>{};
      if (kind == "surface") {
        railvib::validateSurfaceSnapshot("/surface_snapshot", number(m["origin_x_m"]), number(m["origin_y_m"]),
                                         number(m["spacing_x_m"]), number(m["spacing_y_m"]), m["nx"].get<uint64_t>(),
                                         m["ny"].get<uint64_t>(), floats(m["vertical_velocity_m_s"]), limits,
                                         {&vx, &vy});
      } else {
        railvib::validateSectionSnapshot("/section_snapshot", number(m["x_m"]), number(m["origin_y_m"]),
                                         number(m["spacing_y_m"]), m["ny"].get<uint64_t>(), numbers(m["depth_m"]),
                                         floats(m["vertical_velocity_m_s"]), limits, {&vx, &vy});
      }
    } else if (kind == "transform") {
      const std::vector<double> t = numbers(m["translation_m"]), q = numbers(m["rotation_xyzw"]);
      railvib::validateTransform("/tf", m["parent"].get<std::string>(), m["child"].get<std::string>(), t.data(),
                                 q.data());
    } else {
      ADD_FAILURE() << "unknown kind " << kind;
    }
  } catch (const railvib::StreamContractError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MessageContract, EveryCaseOfTheSharedTable) {
  const json table = loadTable();
  railvib::StreamLimits limits;
  limits.velocity_m_s = table["velocity_limit_m_s"].get<double>();
  const auto sensors = table["sensors"].get<std::vector<std::string>>();
  int refused = 0, accepted = 0;
  for (const auto& c : table["cases"]) {
    const std::string kind = c["kind"].get<std::string>();
    json message = table["valid"][kind];
    for (const auto& [key, value] : c["set"].items()) message[key] = value;
    const std::string error = verdictOf(kind, message, limits, sensors);
    const std::string label = kind + ": " + c["name"].get<std::string>();
    if (c["refused"].is_null()) {
      EXPECT_EQ(error, "") << label;
      ++accepted;
    } else {
      const std::string field = c["refused"].get<std::string>();
      EXPECT_NE(error.find(field), std::string::npos)
          << label << ": refusal should name " << field << ": '" << error << "'";
      EXPECT_EQ(error.rfind("topic /", 0), 0u) << label << ": " << error;
      ++refused;
    }
  }
  EXPECT_GE(refused, 40);
  EXPECT_GE(accepted, 8);
}

// A valid surface snapshot with any field mutated (counts, sizes, values): refused or accepted, never
// read out of bounds; accepted exactly when an independent check finds it whole.
TEST(MessageContract, SurfaceSnapshotMutationFuzz) {
  std::mt19937_64 rng(20261206);
  railvib::StreamLimits limits;
  const std::vector<double> specials = {0.0, -1.0, 1e-12, 1e9, std::nan(""), std::numeric_limits<double>::infinity()};
  int refused = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    uint64_t nx = 1 + rng() % 7, ny = 1 + rng() % 5;
    double ox = -10.0, oy = -2.0, sx = 0.5, sy = 0.25;
    std::vector<float> v(nx * ny, 1e-3f);
    switch (rng() % 6) {
      case 0:
        nx = rng() % 3 == 0 ? 0 : (rng() % 2 ? 4294967295ull : nx + 1);
        break;
      case 1:
        v.resize(rng() % (v.size() + 2));
        break;
      case 2:
        v[rng() % v.size()] = static_cast<float>(specials[rng() % specials.size()]);
        break;
      case 3:
        sx = specials[rng() % specials.size()];
        break;
      case 4:
        oy = specials[rng() % specials.size()];
        break;
      default:
        break;
    }
    bool whole = nx >= 1 && ny >= 1 && nx * ny <= railvib::kMaxSnapshotValues && v.size() == nx * ny &&
                 std::isfinite(ox) && std::fabs(oy) <= railvib::kMaxTranslationM && sx >= 1e-9 &&
                 sx <= railvib::kMaxTranslationM && sy > 0.0;
    for (float x : v) whole = whole && std::fabs(x) <= limits.velocity_m_s;
    bool accepted = true;
    try {
      railvib::validateSurfaceSnapshot("/surface_snapshot", ox, oy, sx, sy, nx, ny, v, limits, {});
    } catch (const railvib::StreamContractError& e) {
      accepted = false;
      ++refused;
      EXPECT_NE(std::string(e.what()).find("/surface_snapshot"), std::string::npos);
    }
    EXPECT_EQ(accepted, whole) << "trial " << trial << ": nx " << nx << " ny " << ny << " values " << v.size()
                               << " spacing " << sx << " origin_y " << oy;
  }
  EXPECT_GT(refused, 500);
}
