// railvib/validation: the chain held against what the paper itself reports.
//
// Every quantitative and qualitative statement of Kouroussis et al. (the seed
// paper) that railvib can compute is a Claim: the statement, the criterion it
// is judged by, our number, the verdict (agrees / differs / pending) and the
// verdict recorded in docs/validation.md ("expected"). A claim that agreed and
// now differs is a regression (railvib_tool validate exits 4).
//
//   modelClaims   track receptance and its k_b/k_f dependence, vehicle modes on
//                 rigid and flexible track, wheel impedances, the defect's
//                 spectrum, the impact times, building modes and transfer
//                 functions: seconds (quick) to a minute (full)
//   chainClaims   ground spectra at 2 m and 8 m, Winkler vs CLM free field,
//                 house vs free field, first floor vs ground floor, KB_F:
//                 from the virtual-sensor records of a chain run (a bag of
//                 `./railvib run`, through scripts/validation_chain.py)
//   readings      the readings of the paper's vehicle parameters for the
//                 half-vehicle model (per wheel / per axle / per bogie side,
//                 pitch inertias) run side by side against the paper's
//                 statements, the evidence for the defaults in config/vehicle_t2000.yaml
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "railvib/common/config.hpp"

namespace railvib::validation {

enum class Verdict { Agrees, Differs, Pending };
std::string verdictName(Verdict v);
/// A judged claim's verdict: Agrees when its criterion holds, else Differs.
inline Verdict verdictOf(bool agrees) { return agrees ? Verdict::Agrees : Verdict::Differs; }

struct Claim {
  std::string id;         ///< e.g. "track.first_resonance.winkler"
  std::string topic;      ///< track | vehicle | impedance | defect | passage | building | chain
  std::string paper;      ///< the paper's statement (section)
  std::string criterion;  ///< how our number is judged
  std::string ours;       ///< our number(s)
  Verdict verdict = Verdict::Pending;
  Verdict expected = Verdict::Pending;  ///< the verdict recorded in docs/validation.md
  std::string command;                  ///< a command that regenerates the number
  std::string cause;                    ///< where it differs: the cause found
  /// A claim that agreed (expected) and now differs. A claim left pending (its input not given,
  /// e.g. no Winkler run) is not judged, hence not a regression.
  bool regressed() const { return expected == Verdict::Agrees && verdict == Verdict::Differs; }
};

/// A claim to judge: its id, topic, the paper's statement and the criterion.
Claim claim(std::string id, std::string topic, std::string paper, std::string criterion);
nlohmann::json toJson(const Claim& claim);

struct ValidationOptions {
  /// Skip the claims that need a passage or the building's impulse response (tens of seconds).
  bool quick = false;
};

/// The claims the models check by themselves (no soil run), on the scenario `cfg`.
std::vector<Claim> modelClaims(const Config& cfg, const ValidationOptions& options = {});

/// Vertical velocity records of the virtual sensors of one chain run.
struct SensorRecords {
  double rate_hz = 0.0;
  std::vector<std::string> names;
  std::vector<std::vector<double>> vz_m_s;  ///< per sensor
  const std::vector<double>* find(const std::string& name) const;
};
/// CSV with a time column `t_s` and a column `<sensor>_vz_m_s` per sensor (railvib_tool soil's
/// receivers.csv, or scripts/validation_chain.py's export of a bag).
SensorRecords readSensorRecords(const std::string& csv_path);

/// The chain claims from the free-field run (CLM foundation, building.coupling one_way: the soil does
/// not see the house, so its sensors and its receiver at the house are the free field without it, the
/// configuration the paper validated against Haren) and, if given, the same run with Winkler, and the
/// same run with building.coupling two_way (the default: the house acts on the soil). The house's
/// claims (floors, KB_F, house vs free field) are judged on the two-way run when it is given, else on
/// the one-way house of the free-field run.
std::vector<Claim> chainClaims(const Config& cfg, const SensorRecords& clm, const SensorRecords* winkler,
                               const SensorRecords* two_way = nullptr);

/// One reading of the paper's vehicle parameters: config overrides on the scenario.
struct Reading {
  std::string name;
  std::string description;
  std::vector<std::string> overrides;
};
/// The readings of the T2000 appendix: each factor alone and the combinations that matter.
std::vector<Reading> t2000Readings(const Config& cfg);
/// Runs each reading: modes (rigid, CLM, Winkler), drops, mass, optionally a short passage over the
/// defect (the ringing of the contact force after the impact). `file`/`overrides`: the scenario.
nlohmann::json evaluateReadings(const std::string& file, const std::vector<std::string>& overrides, bool with_passage);

}  // namespace railvib::validation
