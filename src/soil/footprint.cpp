#include "railvib/soil/footprint.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace railvib::soil {
namespace {

// Integral of the 1D hat function of node xi (support [xi - h_left, xi + h_right]) over [a, b].
double hatIntegral(double xi, double h_left, double h_right, double a, double b) {
  auto prim = [&](double x) {
    if (x <= xi - h_left) return 0.0;
    if (x <= xi) {
      const double s = x - (xi - h_left);
      return s * s / (2.0 * h_left);
    }
    if (x < xi + h_right) {
      const double s = xi + h_right - x;
      return 0.5 * h_left + 0.5 * h_right - s * s / (2.0 * h_right);
    }
    return 0.5 * h_left + 0.5 * h_right;
  };
  return prim(b) - prim(a);
}

// The nodes of a uniform 1D grid (n + 1 nodes from x0, step h) whose hat functions may touch [a, b].
std::pair<long, long> nodesAround(double x0, double h, size_t n, double a, double b) {
  return {std::max<long>(0, static_cast<long>(std::floor((a - x0) / h)) - 1),
          std::min<long>(static_cast<long>(n), static_cast<long>(std::ceil((b - x0) / h)) + 1)};
}

// Weights of the nodes of a uniform 1D grid (n + 1 nodes from x0, step h) for a
// uniform load on [a, b] (consistent nodal loads, sum 1 when [a, b] is inside).
std::vector<std::pair<size_t, double>> lineWeights(double x0, double h, size_t n, double a, double b) {
  std::vector<std::pair<size_t, double>> w;
  const auto [i0, i1] = nodesAround(x0, h, n, a, b);
  for (long i = i0; i <= i1; ++i) {
    const double xi = x0 + h * static_cast<double>(i);
    const double hl = i == 0 ? 1e-300 : h, hr = i == static_cast<long>(n) ? 1e-300 : h;
    const double v = hatIntegral(xi, hl, hr, a, b) / (b - a);
    if (v > 0.0) w.emplace_back(static_cast<size_t>(i), v);
  }
  return w;
}

// Integrals of the 1D hat functions of a uniform grid against s over [a, b] (first moments): on each
// piece between nodes the integrand is quadratic, so two Gauss points per piece are exact.
std::vector<std::pair<size_t, double>> lineFirstMoments(double x0, double h, size_t n, double a, double b) {
  std::vector<std::pair<size_t, double>> w;
  const auto [i0, i1] = nodesAround(x0, h, n, a, b);
  const double g = 0.5 / std::sqrt(3.0);
  for (long i = i0; i <= i1; ++i) {
    const double xi = x0 + h * static_cast<double>(i);
    double sum = 0.0;
    for (int side = -1; side <= 1; side += 2) {  // the hat's left and right pieces
      const double lo = std::max(a, side < 0 ? xi - h : xi), hi = std::min(b, side < 0 ? xi : xi + h);
      if (hi <= lo) continue;
      const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
      for (double q : {mid - 2.0 * g * half, mid + 2.0 * g * half}) {
        const double hat = std::max(0.0, 1.0 - std::abs(q - xi) / h);
        sum += half * hat * q;
      }
    }
    if (sum != 0.0) w.emplace_back(static_cast<size_t>(i), sum);
  }
  return w;
}

}  // namespace

ForceChannel railSeatFootprint(const StructuredMesh& m, double x_m, double seat_y_m, const TrackLayout& layout) {
  // The uniform part (the whole footprint's weights) plus the linear part 12 y_s y / L^3 across the track.
  ForceChannel ch = sleeperFootprint(m, x_m, layout);
  const double hl = 0.5 * layout.length_m, hw = 0.5 * layout.width_m, len = layout.length_m;
  const auto wx = lineWeights(m.x0, m.hx, m.nx, x_m - hw, x_m + hw);
  const auto my = lineFirstMoments(m.y0, m.hy, m.ny, -hl, hl);
  const double slope = 12.0 * seat_y_m / (len * len * len);
  for (const auto& [i, a] : wx) {
    for (const auto& [j, b] : my) {
      const size_t node = m.node(i, j, 0);
      const auto it = std::find(ch.nodes.begin(), ch.nodes.end(), node);
      if (it == ch.nodes.end()) {
        ch.nodes.push_back(node);
        ch.components.push_back(2);
        ch.weights.push_back(a * slope * b);
      } else {
        ch.weights[static_cast<size_t>(it - ch.nodes.begin())] += a * slope * b;
      }
    }
  }
  return ch;
}

ForceChannel sleeperFootprint(const StructuredMesh& m, double x_m, const TrackLayout& layout) {
  const double hl = 0.5 * layout.length_m, hw = 0.5 * layout.width_m;
  ForceChannel ch;
  const auto wx = lineWeights(m.x0, m.hx, m.nx, x_m - hw, x_m + hw);
  const auto wy = lineWeights(m.y0, m.hy, m.ny, -hl, hl);
  for (const auto& [i, a] : wx) {
    for (const auto& [j, b] : wy) {
      ch.nodes.push_back(m.node(i, j, 0));
      ch.components.push_back(2);
      ch.weights.push_back(a * b);
    }
  }
  return ch;
}

bool LoadableRegion::holds(double x_m, const TrackLayout& layout) const {
  const double hl = 0.5 * layout.length_m, hw = 0.5 * layout.width_m;
  return x_m - hw >= x_min_m - 1e-9 && x_m + hw <= x_max_m + 1e-9 && -hl >= y_min_m - 1e-9 && hl <= y_max_m + 1e-9;
}

LoadableRegion loadableRegion(const Solver& solver, const AbsorbingFaces& faces) {
  const StructuredMesh& m = solver.mesh();
  const SoilBoundary& boundary = solver.boundary();
  LoadableRegion r;
  r.zone_m = boundary.zoneTakesLoads() ? 0.0 : boundary.zoneThicknessM();
  r.x_min_m = m.x0 + (faces.x_min ? r.zone_m : 0.0);
  r.x_max_m = m.xMax() - (faces.x_max ? r.zone_m : 0.0);
  r.y_min_m = m.y0 + (faces.y_min ? r.zone_m : 0.0);
  r.y_max_m = m.yMax() - (faces.y_max ? r.zone_m : 0.0);
  return r;
}

bool footprintInsideMesh(const StructuredMesh& m, double x_m, const TrackLayout& layout) {
  return LoadableRegion{m.x0, m.xMax(), m.y0, m.yMax(), 0.0}.holds(x_m, layout);
}

}  // namespace railvib::soil
