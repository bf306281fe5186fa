// railvib_tool validate: the chain held against the paper's claims (docs/validation.md).
#include <chrono>
#include <iostream>
#include <optional>

#include "command_registry.hpp"
#include "railvib/io/atomic_file.hpp"
#include "railvib/validation/validation.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;

std::string markdownCell(std::string s) {
  for (auto& ch : s) {
    if (ch == '|') ch = '/';
  }
  return s;
}

int validate(const std::vector<std::string>& args) {
  ArgParser p("validate",
              "every claim of the paper railvib can compute, our number, the verdict; exit 4 when a claim that "
              "agreed (docs/validation.md) now differs");
  addConfigOptions(p);
  p.flag("quick", "skip the claims that need a passage or the building's impulse response (for the test suite)");
  p.flag("readings", "also run the readings of the paper's vehicle parameters (modes, mass; see --readings-passage)");
  p.flag("readings-passage", "with --readings: also a short passage per reading (ringing after the impact)");
  p.option("chain",
           "virtual-sensor records of the free-field chain run: CLM, building.coupling one_way (CSV t_s, "
           "<sensor>_vz_m_s; scripts/validation_chain.py)",
           "");
  p.option("chain-winkler", "the same for the free-field run with Winkler (chain.winkler_vs_clm)", "");
  p.option("chain-two-way",
           "the same for the run with building.coupling two_way, the default (the house's claims, "
           "chain.house_amplitude_reduction)",
           "");
  p.flag("no-models", "with --chain: only the chain claims");
  p.option("markdown", "also write the table as Markdown to this file", "");
  if (!p.parse(args)) return 0;
  const Config cfg = loadConfig(p);
  const auto t0 = std::chrono::steady_clock::now();
  validation::ValidationOptions opt;
  opt.quick = p.isSet("quick");
  std::vector<validation::Claim> claims;
  if (!p.isSet("no-models")) claims = validation::modelClaims(cfg, opt);
  if (p.has("chain") && !p.get("chain").empty()) {
    const validation::SensorRecords clm = validation::readSensorRecords(p.get("chain"));
    // the records of an optional companion run, empty when its option is not given
    auto companion = [&](const std::string& option) {
      return p.has(option) && !p.get(option).empty() ? std::optional(validation::readSensorRecords(p.get(option)))
                                                     : std::nullopt;
    };
    const auto wink = companion("chain-winkler"), two_way = companion("chain-two-way");
    for (auto& c : validation::chainClaims(cfg, clm, wink ? &*wink : nullptr, two_way ? &*two_way : nullptr))
      claims.push_back(c);
  }
  json table = json::array();
  int agrees = 0, differs = 0, pending = 0;
  std::vector<std::string> regressions;
  for (const auto& c : claims) {
    table.push_back(validation::toJson(c));
    agrees += c.verdict == validation::Verdict::Agrees;
    differs += c.verdict == validation::Verdict::Differs;
    pending += c.verdict == validation::Verdict::Pending;
    if (c.regressed()) regressions.push_back(c.id);
  }
  json out = {
      {"claims", table}, {"agrees", agrees}, {"differs", differs}, {"pending", pending}, {"regressions", regressions}};
  if (p.isSet("readings")) {
    std::vector<std::string> overrides;
    for (const auto& s : p.getAll("set")) overrides.push_back(s);
    out["readings"] = validation::evaluateReadings(cfg.file(), overrides, p.isSet("readings-passage"));
  }
  out["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (p.has("markdown") && !p.get("markdown").empty()) {
    io::AtomicFile f(p.get("markdown"));
    f.stream() << "| claim (paper) | criterion | railvib | verdict | cause where it differs |\n|---|---|---|---|---|\n";
    for (const auto& c : claims) {
      f.stream() << "| " << markdownCell(c.paper) << " `" << c.id << "` | " << markdownCell(c.criterion) << " | "
                 << markdownCell(c.ours) << " | " << validation::verdictName(c.verdict) << " | "
                 << markdownCell(c.cause) << " |\n";
    }
    f.commit();
  }
  printJson(out);
  if (!regressions.empty()) {
    std::cerr << "validate: " << regressions.size() << " claim(s) that agreed now differ:";
    for (const auto& id : regressions) std::cerr << " " << id;
    std::cerr << "\n";
    return 4;
  }
  return 0;
}

const Registrar reg_validate("validate", "the paper's claims against railvib's numbers, with verdicts", validate);

}  // namespace
}  // namespace railvib::tool
