#include "railvib/vehicle/resilient_wheel.hpp"

#include <algorithm>
#include <cmath>

#include "railvib/vehicle/modal.hpp"

namespace railvib::vehicle {

namespace {

/// The elements holding body `spec` (an index of params().bodies), as indices of params().suspensions.
std::vector<size_t> elementsOf(const VehicleParams& p, int spec) {
  std::vector<size_t> e;
  for (size_t i = 0; i < p.suspensions.size(); ++i) {
    if (p.suspensions[i].lower_body == spec || p.suspensions[i].upper_body == spec) e.push_back(i);
  }
  return e;
}

/// Share of an element on the modelled rail (vehicle_model.cpp: a centre-line element with
/// body_share_per_rail, one of a side once).
double elementShare(const VehicleParams& p, const SuspensionSpec& e) {
  return e.y_m == 0.0 ? p.body_share_per_rail : 1.0;
}

}  // namespace

std::optional<ResilientWheelChain> resilientWheelChain(const VehicleModel& model, int wheel) {
  const VehicleParams& p = model.params();
  if (model.fullWidth() || wheel < 0 || wheel >= model.wheelCount()) return std::nullopt;
  const BodyInfo& tread_body = model.bodies()[static_cast<size_t>(model.wheels()[wheel].body)];
  const int tread = tread_body.spec;
  if (p.bodies[static_cast<size_t>(tread)].kind != BodyKind::Tread) return std::nullopt;
  const std::vector<size_t> ring_el = elementsOf(p, tread);
  if (ring_el.size() != 1) return std::nullopt;
  const SuspensionSpec& ring = p.suspensions[ring_el[0]];
  const int hub = ring.upper_body == tread ? ring.lower_body : ring.upper_body;
  if (p.bodies[static_cast<size_t>(hub)].hasPitch()) return std::nullopt;
  std::vector<size_t> hub_el = elementsOf(p, hub);
  hub_el.erase(std::remove(hub_el.begin(), hub_el.end(), ring_el[0]), hub_el.end());
  if (hub_el.size() != 1) return std::nullopt;
  const SuspensionSpec& primary = p.suspensions[hub_el[0]];
  const int upper = primary.upper_body == hub ? primary.lower_body : primary.upper_body;
  // masses on the rail: the model's own (a centre-line hub with body_share_per_rail)
  auto massOf = [&](int spec) {
    for (const BodyInfo& b : model.bodies()) {
      if (b.spec == spec) return model.fullMassDiagonal()[b.z_dof];
    }
    return 0.0;
  };
  ResilientWheelChain c;
  c.tread = p.bodies[static_cast<size_t>(tread)].name;
  c.hub = p.bodies[static_cast<size_t>(hub)].name;
  c.upper = p.bodies[static_cast<size_t>(upper)].name;
  c.tread_mass_kg = massOf(tread);
  c.hub_mass_kg = massOf(hub);
  c.upper_mass_kg = massOf(upper);
  c.ring_stiffness_n_m = elementShare(p, ring) * ring.stiffness_n_m;
  c.ring_damping_n_s_m = elementShare(p, ring) * ring.damping_n_s_m;
  c.primary_stiffness_n_m = elementShare(p, primary) * primary.stiffness_n_m;
  c.primary_damping_n_s_m = elementShare(p, primary) * primary.damping_n_s_m;
  c.hertz_stiffness_n_m = linearisedHertzStiffness(model)[static_cast<size_t>(wheel)];
  return c;
}

std::complex<double> resilientWheelImpedance(const ResilientWheelChain& c, double f_hz, ChainTop top) {
  using cd = std::complex<double>;
  const double w = 2.0 * M_PI * f_hz;
  const cd iw(0.0, w);
  const cd s_p = c.primary_stiffness_n_m + iw * c.primary_damping_n_s_m;
  const cd s_t = c.ring_stiffness_n_m + iw * c.ring_damping_n_s_m;
  // the hub's element in series with the body above: s_p D_u / (s_p + D_u), s_p when blocked
  cd above = s_p;
  if (top == ChainTop::FreeMass) {
    const cd d_u = -w * w * c.upper_mass_kg;
    above = s_p * d_u / (s_p + d_u);
  }
  const cd d_h = -w * w * c.hub_mass_kg + above;
  const cd d_t = c.hertz_stiffness_n_m - w * w * c.tread_mass_kg + s_t * d_h / (s_t + d_h);
  return d_t / iw;
}

std::vector<double> resilientWheelFrequencies(const ResilientWheelChain& c, ChainTop top) {
  const double m_t = c.tread_mass_kg, m_h = c.hub_mass_kg, M = c.upper_mass_kg;
  const double k_t = c.ring_stiffness_n_m, k_p = c.primary_stiffness_n_m, k_h = c.hertz_stiffness_n_m;
  std::vector<double> lambda;  // w^2
  if (top == ChainTop::Blocked) {
    // (k_t + k_H - l m_t)(k_t + k_p - l m_h) - k_t^2 = 0
    const double a = m_t * m_h;
    const double b = -(m_t * (k_t + k_p) + m_h * (k_t + k_h));
    const double q = (k_t + k_h) * (k_t + k_p) - k_t * k_t;
    const double disc = std::sqrt(b * b - 4.0 * a * q);
    // the smaller root as q / (a l_max): no cancellation
    const double l_max = (-b + disc) / (2.0 * a);
    lambda = {q / (a * l_max), l_max};
  } else {
    // det of the tridiagonal chain [M, m_h, m_t] by its continuant:
    // f1 = k_p - l M, f2 = (k_p + k_t - l m_h) f1 - k_p^2, f3 = (k_t + k_H - l m_t) f2 - k_t^2 f1,
    // as polynomials in l (coefficients, lowest first)
    using Poly = std::vector<double>;
    auto mul = [](const Poly& x, const Poly& y) {
      Poly r(x.size() + y.size() - 1, 0.0);
      for (size_t i = 0; i < x.size(); ++i)
        for (size_t j = 0; j < y.size(); ++j) r[i + j] += x[i] * y[j];
      return r;
    };
    auto add = [](Poly x, const Poly& y, double s) {
      if (x.size() < y.size()) x.resize(y.size(), 0.0);
      for (size_t i = 0; i < y.size(); ++i) x[i] += s * y[i];
      return x;
    };
    const Poly f1{k_p, -M};
    const Poly f2 = add(mul({k_p + k_t, -m_h}, f1), Poly{1.0}, -k_p * k_p);
    const Poly f3 = add(mul({k_t + k_h, -m_t}, f2), f1, -k_t * k_t);
    // l^3 + a2 l^2 + a1 l + a0 = 0, three real positive roots (K, M symmetric positive definite):
    // l = -a2/3 + 2 sqrt(-p/3) cos(phi/3 - 2 pi j/3), the trigonometric form of Cardano's solution
    const double a2 = f3[2] / f3[3], a1 = f3[1] / f3[3], a0 = f3[0] / f3[3];
    const double pp = a1 - a2 * a2 / 3.0;
    const double qq = 2.0 * a2 * a2 * a2 / 27.0 - a2 * a1 / 3.0 + a0;
    const double r = std::sqrt(-pp / 3.0);
    const double arg = std::clamp(-qq / (2.0 * r * r * r), -1.0, 1.0);
    const double phi = std::acos(arg);
    for (int j = 0; j < 3; ++j) lambda.push_back(-a2 / 3.0 + 2.0 * r * std::cos((phi - 2.0 * M_PI * j) / 3.0));
  }
  std::vector<double> f;
  for (double l : lambda) f.push_back(std::sqrt(std::max(0.0, l)) / (2.0 * M_PI));
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace railvib::vehicle
