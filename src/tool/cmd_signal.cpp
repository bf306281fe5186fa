// railvib_tool signal commands: metrics (vibration metrics of a CSV record),
// din-check (DIN 45669-1 KB test table computed vs expected).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "command_registry.hpp"
#include "railvib/common/constants.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/io/csv.hpp"
#include "railvib/signal/decimator.hpp"
#include "railvib/signal/din_check.hpp"
#include "railvib/signal/monitor.hpp"
#include "tool_common.hpp"

namespace railvib::tool {
namespace {

using nlohmann::json;
using namespace railvib::signal;

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// JSON cannot hold -inf (silent band): print null.
json dbValue(double db) { return std::isfinite(db) ? json(std::round(db * 100.0) / 100.0) : json(nullptr); }

int metrics(const std::vector<std::string>& args) {
  ArgParser p("metrics",
              "vibration metrics of a velocity record: DIN 4150-2 KB_Fmax, PPV and DIN 4150-3 verdict, "
              "dominant frequency, one-third-octave levels");
  p.option("csv", "input CSV file (header row, numeric rows)");
  p.option("column", "velocity column(s), comma-separated (e.g. vz or vx,vy,vz)");
  p.option("rate", "sample rate (Hz); default: from the time column");
  p.option("time-column", "time column (s), used when --rate is not given", "t_s");
  p.option("unit", "velocity unit of the columns: m_s | mm_s", "m_s");
  p.option("out", "write KB_F(t) per column to this CSV");
  p.option("period", "DIN 4150-2 period for the verdict: day | night", "day");
  p.option("kind", "where the record was taken: free_field | foundation | floor (which standards apply)", "foundation");
  p.option("resolved-hz",
           "highest frequency the record resolves (a model's f_max; verdicts governed above it are "
           "not assessable); 0 = no limit (a measured record)",
           "0");
  p.option("exposure-s", "DIN 4150-2 exposure time within the rating period (s) for KB_FTr; default: record length");
  p.option("bands", "one-third-octave nominal range min,max (Hz)", "1,100");
  p.option("vref", "reference velocity for levels (m/s): 1e-9 (ISO 1683) or 5e-8", "1e-9");
  if (!p.parse(args)) return 0;
  if (!p.has("csv") || !p.has("column")) throw ArgError("metrics: --csv and --column are required");
  const io::CsvTable table = io::readCsv(p.get("csv"));
  // KB_F's running rms needs two of its 0.125 s time constants to settle (86 %): a shorter record has no metric.
  constexpr size_t kMinSamples = 64;
  constexpr double kMinDurationS = 0.25;
  if (table.rows.size() < kMinSamples) {
    throw std::runtime_error("metrics: " + p.get("csv") + ": " + std::to_string(table.rows.size()) +
                             " samples: too short for the metrics (at least " + std::to_string(kMinSamples) +
                             " samples over " + formatValue(kMinDurationS) + " s)");
  }
  const auto names = splitList(p.get("column"));
  if (names.empty()) throw ArgError("metrics: --column is empty");
  const std::string unit = p.get("unit");
  if (unit != "m_s" && unit != "mm_s") throw ArgError("metrics: --unit must be m_s or mm_s");
  const double to_m_s = unit == "mm_s" ? 1e-3 : 1.0;

  double fs = 0.0;
  if (p.has("rate")) {
    fs = p.getDouble("rate", 1.0, 1e7);
    if (!(fs > 0.0)) throw ArgError("metrics: --rate must be positive");
  } else {
    const double dt = io::uniformStep(table, table.column(p.get("time-column")));
    fs = 1.0 / dt;
  }

  std::vector<std::vector<double>> comps;
  const double bound = StreamLimits{}.velocity_m_s;
  for (const auto& name : names) {
    const size_t c = table.column(name);
    std::vector<double> v(table.rows.size());
    for (size_t i = 0; i < v.size(); ++i) {
      v[i] = table.rows[i][c] * to_m_s;
      // A velocity beyond any ground or building vibration is a unit or file error, not a record.
      if (!(std::abs(v[i]) <= bound)) {
        throw std::runtime_error(table.where(i) + ": column '" + name + "' = " + formatValue(table.rows[i][c]) + " " +
                                 unit + ": beyond the " + formatValue(bound) +
                                 " m/s a particle velocity may be (limits.velocity_m_s)");
      }
    }
    comps.push_back(std::move(v));
  }
  // Length last: a wrong column or an impossible value is the first thing to say about a file.
  if (static_cast<double>(table.rows.size()) / fs < kMinDurationS) {
    throw std::runtime_error("metrics: " + p.get("csv") + ": " + std::to_string(table.rows.size()) + " samples at " +
                             formatValue(fs) + " Hz: " + formatValue(table.rows.size() / fs) +
                             " s, too short for the metrics (at least " + formatValue(kMinDurationS) + " s)");
  }
  const std::vector<double> range = p.getDoubles("bands", 0.1, 20000.0);
  if (range.size() != 2 || !(range[0] < range[1])) throw ArgError("metrics: --bands must be min,max with min < max");
  MonitorSpec spec;
  spec.fs_hz = fs;
  spec.third_octave_min_hz = range[0];
  spec.third_octave_max_hz = range[1];
  spec.v_ref_m_s = p.getDouble("vref", 1e-15, 1.0);
  const RecordMetrics r = evaluateRecord(comps, spec);
  const auto& s = r.summary;
  const double duration = static_cast<double>(comps.front().size()) / fs;

  const std::string period_name = p.get("period");
  if (period_name != "day" && period_name != "night") throw ArgError("metrics: --period must be day or night");
  const Din4150_2Period period = period_name == "day" ? Din4150_2Period::Day : Din4150_2Period::Night;
  const double exposure = p.has("exposure-s") ? p.getDouble("exposure-s", 1e-3, 86400.0) : duration;
  double kb_ftm_max = 0.0;
  for (double v : r.kb_ftm) kb_ftm_max = std::max(kb_ftm_max, v);
  const double kb_ftr = kbFTr(kb_ftm_max, exposure, period);
  SensorKind kind = SensorKind::Foundation;
  try {
    kind = sensorKindFromName(p.get("kind"));
  } catch (const std::invalid_argument& e) {
    throw ArgError(std::string("metrics: --kind: ") + e.what());
  }
  const double resolved_option = p.getDouble("resolved-hz", 0.0, 1e6);
  if (!(resolved_option >= 0.0 && resolved_option <= 1e6)) throw ArgError("metrics: --resolved-hz in [0, 1e6] Hz");
  const double resolved_hz = resolved_option > 0.0 ? resolved_option : std::numeric_limits<double>::infinity();
  // The same verdicts as the live sensors, with the rating KB_FTr the whole record gives.
  const SensorVerdict verdict = sensorVerdict(s, period, kind, resolved_hz, kb_ftr);
  const Din4150_2Verdict& v42 = verdict.din4150_2;
  // met / not met where a standard judges; otherwise why it does not (not applicable, not assessable).
  const auto judged = [](VerdictLevel level, bool met, const char* fails) -> std::string {
    if (level == VerdictLevel::NotApplicable || level == VerdictLevel::NotAssessable) return verdictName(level);
    return met ? "met" : fails;
  };

  json out;
  out["input"] = {
      {"csv", p.get("csv")},   {"columns", names}, {"unit", unit}, {"rate_hz", fs}, {"samples", comps.front().size()},
      {"duration_s", duration}};
  const PpvEvaluation ppv = din4150_3ForKind(s.ppv, kind);  // the guidelines where the record was taken
  json kb_comp = json::array();
  json ppv_comp = json::array();
  json oct_comp = json::array();
  for (size_t c = 0; c < names.size(); ++c) {
    kb_comp.push_back({{"column", names[c]}, {"kb_fmax", s.kb_fmax[c]}, {"kb_ftm", r.kb_ftm[c]}});
    const PpvComponent& pc = ppv.components[c];
    ppv_comp.push_back({{"column", names[c]},
                        {"ppv_mm_s", pc.ppv_mm_s},
                        {"time_s", pc.time_s},
                        {"dominant_frequency_hz", pc.frequency_hz},
                        {"dominant_frequency_method", "zero-crossing half period around the peak"},
                        {"spectral_peak_hz", r.spectral_peak_hz[c]},
                        {"din4150_3_limit_mm_s", pc.limit_mm_s},
                        {"ratio_to_limit", pc.ratio}});
    json levels = json::array();
    for (size_t b = 0; b < s.bands.size(); ++b) {
      // running_level_db: the running level at the end of the record, what a live sensor reports.
      levels.push_back({{"nominal_hz", s.bands[b].nominal_hz},
                        {"level_db", dbValue(s.third_octave_equivalent_db[c][b])},
                        {"running_level_db", dbValue(s.third_octave_running_db[c][b])}});
    }
    oct_comp.push_back({{"column", names[c]}, {"levels", levels}});
  }
  out["din4150_2"] = {{"kb_fmax", s.kb_fmax_all},
                      {"components", kb_comp},
                      {"kb_ftr", kb_ftr},
                      {"exposure_s", exposure},
                      {"period", period_name},
                      {"a_u", v42.guide.a_u},
                      {"a_o", v42.guide.a_o},
                      {"a_r", v42.guide.a_r},
                      {"verdict", judged(v42.level, v42.met, "not met")},
                      {"level", verdictName(v42.level)},
                      {"reason", v42.reason},
                      {"note", "KB_FTr simplified: KB_FTm of 30 s cycles x sqrt(T_e / T_r), no rest-period surcharge"}};
  out["sensor"] = {{"kind", sensorKindName(kind)},
                   {"resolved_hz", resolved_option > 0.0 ? json(resolved_hz) : json(nullptr)},
                   {"verdict", verdictName(verdict.level)},
                   {"reason", verdict.reason}};
  out["din4150_3"] = {{"building", kind == SensorKind::Floor ? "residential, short-term, floors (15 mm/s horizontal, "
                                                               "20 mm/s vertical)"
                                                             : "residential (Table 1 row 2), short-term, foundation"},
                      {"level", verdictName(verdict.din4150_3.level)},
                      {"components", ppv_comp},
                      {"vector_peak_mm_s", s.ppv.vector_peak_mm_s},
                      {"vector_peak_time_s", s.ppv.vector_peak_time_s},
                      {"max_ratio", ppv.max_ratio},
                      {"governing_component", names[std::min(verdict.din4150_3.governing_component, names.size() - 1)]},
                      {"verdict", judged(verdict.din4150_3.level, verdict.din4150_3.met, "exceeded")}};
  out["third_octave"] = {{"v_ref_m_s", spec.v_ref_m_s},
                         {"method", "6th-order Butterworth band filters, equivalent level over the record"},
                         {"components", oct_comp}};

  if (p.has("out")) {
    std::vector<std::string> cols{"t_s"};
    for (const auto& n : names) cols.push_back("kb_f_" + n);
    io::CsvWriter w(p.get("out"), cols);
    std::vector<double> row(cols.size());
    for (size_t i = 0; i < comps.front().size(); ++i) {
      row[0] = static_cast<double>(i) / fs;
      for (size_t c = 0; c < names.size(); ++c) row[c + 1] = r.kb_f[c][i];
      w.row(row);
    }
    w.commit();
    out["kb_f_csv"] = p.get("out");
  }
  printJson(out);
  return 0;
}

int dinCheck(const std::vector<std::string>& args) {
  ArgParser p("din-check",
              "DIN 45669-1 KB test table (continuous 1 mm/s sines): KB_F and KB_Fmax computed vs expected");
  p.option("rate", "sample rate(s) of the digital filters (Hz), comma-separated", "500,1000,2000,8000");
  p.option("tolerance", "relative tolerance for pass", "0.02");
  if (!p.parse(args)) return 0;
  const double tol = p.getDouble("tolerance", 1e-9, 1.0);
  json out;
  out["definition"] =
      "KB_F = steady mean of KB_F(t); KB_Fmax = maximum of its ripple (running rms of a sine oscillates at 2f)";
  out["tolerance"] = tol;
  bool all_pass = true;
  json tables = json::array();
  for (const double fs : p.getDoubles("rate", 300.0, 1.0e6)) {
    json rows = json::array();
    for (const auto& r : din45669TestTable(fs)) {
      const double e1 = r.kb_f / r.expected_kb_f - 1.0;
      const double e2 = r.kb_fmax / r.expected_kb_fmax - 1.0;
      const bool pass = std::abs(e1) <= tol && std::abs(e2) <= tol;
      all_pass = all_pass && pass;
      rows.push_back({{"f_hz", r.f_hz},
                      {"kb_f", r.kb_f},
                      {"kb_f_expected", r.expected_kb_f},
                      {"kb_f_error", e1},
                      {"kb_f_rms", r.kb_f_rms},
                      {"kb_fmax", r.kb_fmax},
                      {"kb_fmax_expected", r.expected_kb_fmax},
                      {"kb_fmax_error", e2},
                      {"kb_fmax_analog", r.kb_fmax_analog},
                      {"pass", pass}});
    }
    tables.push_back({{"rate_hz", fs}, {"rows", rows}});
  }
  out["tables"] = tables;
  out["pass"] = all_pass;
  printJson(out);
  return all_pass ? 0 : 1;
}

int decimatorCheck(const std::vector<std::string>& args) {
  ArgParser p("decimator-check",
              "design figures of the anti-alias decimator: stages, taps, latency, pass-band ripple, stop band, "
              "time alignment of a pass-band sine, cost");
  p.option("input-rate", "input rate (Hz)", "100000");
  p.option("output-rate", "output rate (Hz)", "2000");
  p.option("passband", "pass band edge as a fraction of the output rate", "0.4");
  p.option("channels", "channels for the cost measurement", "100");
  if (!p.parse(args)) return 0;
  DecimatorSpec spec;
  spec.input_rate_hz = p.getDouble("input-rate", 1.0, 1e7);
  spec.output_rate_hz = p.getDouble("output-rate", 1.0, 1e7);
  spec.passband_fraction = p.getDouble("passband", 1e-3, 0.5);
  const double fi = spec.input_rate_hz, fo = spec.output_rate_hz;
  Decimator d(spec, 1);
  double ripple = 0.0, stop = 0.0;
  for (double f = 0.0; f <= spec.passband_fraction * fo; f += fo / 2000.0) {
    ripple = std::max(ripple, std::abs(20.0 * std::log10(d.responseMagnitude(f))));
  }
  for (double f = 0.5 * fo; f <= 0.5 * fi; f += fo / 997.0) stop = std::max(stop, d.responseMagnitude(f));
  // Alignment: a sine at 0.37 f_out against its exact values at t_k = t0 + k / f_out.
  const double fsine = 0.37 * fo, t0 = 0.0123;
  Decimator a(spec, 1, t0);
  std::vector<double> x(static_cast<size_t>(std::max(2.0, 0.5 * fi))), y;
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2.0 * kPi * fsine * (t0 + static_cast<double>(i) / fi));
  a.push(x, y);
  double align = 0.0;
  for (size_t k = static_cast<size_t>(std::ceil(a.halfWidthSeconds() * fo)) + 1; k < y.size(); ++k) {
    align = std::max(align, std::abs(y[k] - std::sin(2.0 * kPi * fsine * a.outputTime(k))));
  }
  // Cost: one simulated second of `channels` channels, blocks of 1000 input frames.
  const size_t nc = static_cast<size_t>(std::max(1L, p.getInt("channels", 1, 10000)));
  Decimator c(spec, nc);
  const size_t block = 1000;
  std::vector<double> in(block * nc, 1.0), out;
  const auto start = std::chrono::steady_clock::now();
  for (double done = 0.0; done < fi; done += static_cast<double>(block)) {
    out.clear();
    c.push(in, out);
  }
  const double cost = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  json out_json = {{"input_rate_hz", fi},
                   {"output_rate_hz", fo},
                   {"integer_ratio", d.integerRatio()},
                   {"stage_ratios", d.stageRatios()},
                   {"equivalent_taps", d.taps().size()},
                   {"latency_input_samples", d.latencyInputSamples()},
                   {"latency_s", d.halfWidthSeconds()},
                   {"passband_ripple_db", ripple},
                   {"stopband_db", 20.0 * std::log10(stop)},
                   {"sine_hz", fsine},
                   {"alignment_max_error", align},
                   {"channels", nc},
                   {"cpu_s_per_simulated_s", cost}};
  printJson(out_json);
  return 0;
}

// The guide values every figure and monitor draws as lines, from the same functions the verdicts use.
int dinGuides(const std::vector<std::string>& args) {
  ArgParser p("din-guides",
              "DIN 4150-2 guide values (residential, day and night) and the DIN 4150-3 residential guideline "
              "curve, as JSON for plots");
  p.option("step-hz", "frequency step of the DIN 4150-3 curve (Hz)", "1");
  p.option("max-hz", "highest frequency of the DIN 4150-3 curve (Hz)", "100");
  if (!p.parse(args)) return 0;
  const double step = p.getDouble("step-hz", 1e-3, 1e3);
  const double f_max = p.getDouble("max-hz", 1e-3, 1e5);
  if (!(step > 0.0 && std::isfinite(step)) || !(f_max > 0.0 && f_max <= 1e4)) {
    throw std::invalid_argument("din-guides: --step-hz must be > 0 and --max-hz in (0, 1e4]");
  }
  json din2 = json::object();
  for (const auto& [name, period] :
       {std::pair{"day", Din4150_2Period::Day}, std::pair{"night", Din4150_2Period::Night}}) {
    const Din4150_2GuideValues g = din4150_2Residential(period);
    din2[name] = {{"a_u", g.a_u}, {"a_o", g.a_o}, {"a_r", g.a_r}};
  }
  json f_hz = json::array(), limit = json::array();
  for (double f = 0.0; f <= f_max + 1e-9; f += step) {
    f_hz.push_back(f);
    limit.push_back(din4150_3ResidentialLimitMmS(f));
  }
  printJson({{"din4150_2_residential", din2},
             {"din4150_3_residential", {{"frequency_hz", f_hz}, {"limit_mm_s", limit}}},
             {"din4150_3_floors",
              {{"horizontal_mm_s", kDin4150_3FloorHorizontalMmS}, {"vertical_mm_s", kDin4150_3FloorVerticalMmS}}}});
  return 0;
}

const Registrar kMetrics("metrics", "vibration metrics of a velocity CSV (KB_Fmax, PPV/DIN 4150-3, 1/3 octave)",
                         metrics);
const Registrar kDinGuides("din-guides", "DIN 4150-2 guide values and the DIN 4150-3 guideline curve (JSON)",
                           dinGuides);
const Registrar kDinCheck("din-check", "DIN 45669-1 KB test table computed vs expected", dinCheck);
const Registrar kDecimatorCheck("decimator-check", "anti-alias decimator design figures (ripple, stop band, latency)",
                                decimatorCheck);

}  // namespace
}  // namespace railvib::tool
