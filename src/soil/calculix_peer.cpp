#include "railvib/soil/calculix_peer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "railvib/soil/solver.hpp"

namespace railvib::soil {

namespace {

// The load amplitude: a Hann pulse sampled at amplitude_points over pulse_s, zero after; linear between.
std::vector<std::pair<double, double>> amplitudePolyline(const PeerCase& c) {
  std::vector<std::pair<double, double>> p;
  const size_t n = std::max<size_t>(2, c.amplitude_points);
  for (size_t q = 0; q < n; ++q) {
    const double t = c.pulse_s * static_cast<double>(q) / static_cast<double>(n - 1);
    p.emplace_back(t, 0.5 - 0.5 * std::cos(2.0 * M_PI * t / c.pulse_s));
  }
  p.back().second = 0.0;
  p.emplace_back(std::max(c.duration_s, c.pulse_s) + 1.0, 0.0);
  return p;
}

double amplitudeAt(const std::vector<std::pair<double, double>>& p, double t) {
  if (t <= p.front().first) return p.front().second;
  for (size_t q = 1; q < p.size(); ++q) {
    if (t <= p[q].first) {
      const double s = (t - p[q - 1].first) / (p[q].first - p[q - 1].first);
      return p[q - 1].second + s * (p[q].second - p[q - 1].second);
    }
  }
  return p.back().second;
}

size_t outputSteps(const PeerCase& c) {
  return static_cast<size_t>(std::llround(c.duration_s / c.dt_s)) / std::max<size_t>(1, c.output_every);
}

}  // namespace

PeerCase voidPeerCase() {
  const Material layer1{61.0e6, 1876.0, 0.13}, layer2{84.0e6, 1876.0, 0.13};
  std::vector<double> z{0.0};
  std::vector<Material> mats;
  for (size_t k = 0; k < 8; ++k) {
    z.push_back(z.back() + (k < 4 ? 0.2 : 0.3));
    mats.push_back(k < 4 ? layer1 : layer2);
  }
  PeerCase c;
  c.mesh = buildUniformMesh(12, 10, 0.25, 0.25, z, mats, -1.5, -1.25);
  InclusionSpec pit;
  pit.name = "pit";
  pit.is_void = true;
  pit.x_min_m = -0.5, pit.x_max_m = 0.25, pit.y_min_m = -0.5, pit.y_max_m = 0.5, pit.top_m = 0.0, pit.bottom_m = 1.1;
  InclusionSpec block = pit;
  block.name = "block";
  block.is_void = false;
  block.material = {20.0e9, 2400.0, 0.2};
  block.x_min_m = 0.5, block.x_max_m = 1.0, block.top_m = 0.2, block.bottom_m = 0.8;
  addInclusions(c.mesh, {pit, block}, 1e-9);
  const StructuredMesh& m = c.mesh;
  c.load_i = 2, c.load_j = 5;
  c.dt_s = 1.0e-5;
  c.duration_s = 0.04;
  // The load point; the pit's near wall, floor and far rim; the block's top; a far corner.
  c.output_nodes = {m.node(2, 5, 0), m.node(4, 5, 2), m.node(6, 5, 5),
                    m.node(8, 5, 0), m.node(9, 5, 1), m.node(11, 9, 0)};
  return c;
}

std::string calculixInput(const PeerCase& c) {
  const StructuredMesh& m = c.mesh;
  std::ostringstream out;
  // CalculiX reads at most 20 characters per field: 12 significant digits fit, sign and exponent included.
  out << std::setprecision(12);
  out << "** railvib soil peer case (railvib_tool soil-bench void-peer): " << m.nx << " x " << m.ny << " x " << m.nz
      << " box, " << m.inclusions.size() << " inclusion(s); z up, depth = -z\n";
  // Solid elements by material; the nodes they use.
  std::map<std::tuple<double, double, double>, std::vector<std::array<size_t, 8>>> by_material;
  std::vector<char> used(m.nodeCount(), 0);
  for (size_t k = 0; k < m.nz; ++k) {
    for (size_t j = 0; j < m.ny; ++j) {
      for (size_t i = 0; i < m.nx; ++i) {
        const Material* mat = m.elementMaterial(i, j, k);
        if (!mat) continue;
        // C3D8: the face nearer the bottom (level k + 1, lower z) counter-clockwise seen from above, then the top.
        const std::array<size_t, 8> e = {m.node(i, j, k + 1),     m.node(i + 1, j, k + 1), m.node(i + 1, j + 1, k + 1),
                                         m.node(i, j + 1, k + 1), m.node(i, j, k),         m.node(i + 1, j, k),
                                         m.node(i + 1, j + 1, k), m.node(i, j + 1, k)};
        for (size_t nd : e) used[nd] = 1;
        by_material[{mat->young_modulus_pa, mat->density_kg_m3, mat->poisson_ratio}].push_back(e);
      }
    }
  }
  out << "*NODE, NSET=NALL\n";
  for (size_t k = 0; k <= m.nz; ++k) {
    for (size_t j = 0; j <= m.ny; ++j) {
      for (size_t i = 0; i <= m.nx; ++i) {
        const size_t nd = m.node(i, j, k);
        if (used[nd]) out << nd + 1 << ", " << m.x(i) << ", " << m.y(j) << ", " << -m.z[k] << "\n";
      }
    }
  }
  size_t id = 1, set = 1;
  for (const auto& [key, elements] : by_material) {
    out << "*ELEMENT, TYPE=C3D8, ELSET=E" << set << "\n";
    for (const auto& e : elements) {
      out << id++;
      for (size_t nd : e) out << ", " << nd + 1;
      out << "\n";
    }
    out << "*MATERIAL, NAME=M" << set << "\n*ELASTIC\n"
        << std::get<0>(key) << ", " << std::get<2>(key) << "\n*DENSITY\n"
        << std::get<1>(key) << "\n*SOLID SECTION, ELSET=E" << set << ", MATERIAL=M" << set << "\n";
    ++set;
  }
  out << "*NSET, NSET=BOTTOM\n";
  size_t count = 0;
  for (size_t j = 0; j <= m.ny; ++j) {
    for (size_t i = 0; i <= m.nx; ++i) {
      const size_t nd = m.node(i, j, m.nz);
      if (!used[nd]) continue;
      out << nd + 1 << (++count % 12 == 0 ? ",\n" : ", ");
    }
  }
  out << "\n*NSET, NSET=OUT\n";
  for (size_t q = 0; q < c.output_nodes.size(); ++q)
    out << c.output_nodes[q] + 1 << (q + 1 < c.output_nodes.size() ? ", " : "\n");
  out << "*BOUNDARY\nBOTTOM, 1, 3\n*AMPLITUDE, NAME=PULSE\n";
  const auto poly = amplitudePolyline(c);
  for (size_t q = 0; q < poly.size(); ++q) {
    out << poly[q].first << ", " << poly[q].second << (q % 4 == 3 || q + 1 == poly.size() ? "\n" : ", ");
  }
  // Pure central difference (ALPHA = 0: no numerical damping); the increment fixed at dt.
  out << "*STEP, INC=100000000\n*DYNAMIC, EXPLICIT, ALPHA=0.0\n"
      << c.dt_s << ", " << c.duration_s << ", " << c.dt_s << ", " << c.dt_s << "\n"
      << "*CLOAD, AMPLITUDE=PULSE\n"
      << m.node(c.load_i, c.load_j, 0) + 1 << ", 3, " << -c.peak_force_n << "\n"
      << "*NODE PRINT, NSET=OUT, FREQUENCY=" << c.output_every << "\nU\n*END STEP\n";
  return out.str();
}

PeerHistory readCalculixDisplacements(const std::string& dat_text, const PeerCase& c) {
  std::map<size_t, size_t> slot;  // CalculiX node id -> output position
  for (size_t q = 0; q < c.output_nodes.size(); ++q) slot[c.output_nodes[q] + 1] = q;
  const size_t steps = outputSteps(c);
  const double period = c.dt_s * static_cast<double>(c.output_every);
  PeerHistory h;
  h.time_s.resize(steps);
  h.u_m.assign(steps * 3 * c.output_nodes.size(), 0.0);
  std::vector<size_t> seen(steps, 0);
  std::istringstream in(dat_text);
  std::string line;
  long block = -1;
  while (std::getline(in, line)) {
    const size_t at = line.find("displacements (vx,vy,vz) for set OUT and time");
    if (at != std::string::npos) {
      const double t = std::stod(line.substr(line.rfind(' ') + 1));
      const long n = std::lround(t / period);
      // Blocks at the output times only (CalculiX may add one at the step's end).
      block =
          (n >= 1 && static_cast<size_t>(n) <= steps && std::abs(t - static_cast<double>(n) * period) < 0.01 * period)
              ? n - 1
              : -1;
      if (block >= 0) h.time_s[static_cast<size_t>(block)] = t, seen[static_cast<size_t>(block)] = 0;
      continue;
    }
    if (block < 0) continue;
    std::istringstream ls(line);
    size_t id = 0;
    double u[3];
    if (!(ls >> id >> u[0] >> u[1] >> u[2])) continue;
    const auto it = slot.find(id);
    if (it == slot.end())
      throw std::runtime_error("calculix output: node " + std::to_string(id) + " was not asked for");
    double* dst = &h.u_m[(static_cast<size_t>(block) * c.output_nodes.size() + it->second) * 3];
    dst[0] = u[0], dst[1] = u[1], dst[2] = -u[2];  // z up -> depth down
    ++seen[static_cast<size_t>(block)];
  }
  for (size_t b = 0; b < steps; ++b) {
    if (seen[b] != c.output_nodes.size()) {
      throw std::runtime_error("calculix output: " + std::to_string(seen[b]) + " of " +
                               std::to_string(c.output_nodes.size()) + " nodes at output " + std::to_string(b + 1) +
                               " of " + std::to_string(steps) + " (did the run finish?)");
    }
  }
  return h;
}

PeerHistory runPeerCase(const PeerCase& c) {
  SolverOptions o;
  o.absorbing = {false, false, false, false, false};
  o.fixed_bottom = true;
  o.kernel = KernelKind::Stencil;
  o.precision = Precision::Double;
  o.threads = 1;
  o.dt_s = c.dt_s;
  Solver s(c.mesh, o);
  s.addForceChannel({{c.mesh.node(c.load_i, c.load_j, 0)}, {2}, {c.peak_force_n}});
  const auto poly = amplitudePolyline(c);
  const size_t steps = outputSteps(c);
  PeerHistory h;
  for (size_t b = 0; b < steps; ++b) {
    for (size_t q = 0; q < c.output_every; ++q) {
      s.setChannelValues({amplitudeAt(poly, s.time())});
      s.step();
    }
    h.time_s.push_back(s.time());
    for (size_t nd : c.output_nodes) {
      for (int d = 0; d < 3; ++d) h.u_m.push_back(s.displacement(nd, d));
    }
  }
  return h;
}

double peerDifference(const PeerHistory& a, const PeerHistory& b) {
  const size_t times = b.time_s.size();
  if (a.u_m.size() != b.u_m.size() || b.u_m.empty() || times == 0 || b.u_m.size() % (3 * times) != 0) return INFINITY;
  const size_t nodes = b.u_m.size() / (3 * times);
  double worst = 0.0;
  for (size_t q = 0; q < nodes; ++q) {
    double diff = 0.0, peak = 0.0;
    for (size_t t = 0; t < times; ++t) {
      for (size_t d = 0; d < 3; ++d) {
        const size_t at = (t * nodes + q) * 3 + d;
        diff = std::max(diff, std::abs(a.u_m[at] - b.u_m[at]));
        peak = std::max(peak, std::abs(b.u_m[at]));
      }
    }
    worst = std::max(worst, peak > 0.0 ? diff / peak : (diff > 0.0 ? INFINITY : 0.0));
  }
  return worst;
}

}  // namespace railvib::soil
