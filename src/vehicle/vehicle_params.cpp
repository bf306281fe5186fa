#include "railvib/vehicle/vehicle_params.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "railvib/common/site.hpp"
#include "railvib/common/stream_contract.hpp"
#include "railvib/vehicle/vehicle_model.hpp"

namespace railvib::vehicle {

namespace {
std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

std::vector<double> VehicleParams::axleOffsets() const {
  std::vector<double> x;
  for (const WheelSpec& w : wheels) x.push_back(bodies.at(static_cast<size_t>(w.body)).x_m);
  return x;
}

int VehicleParams::bodyIndex(const std::string& body_name) const {
  for (size_t b = 0; b < bodies.size(); ++b) {
    if (bodies[b].name == body_name) return static_cast<int>(b);
  }
  return -1;
}

namespace {

/// Keys of a map section, in file order.
std::vector<std::string> keysOf(const ConfigNode& node) {
  std::vector<std::string> keys;
  for (const auto& kv : node.yaml()) keys.push_back(kv.first.as<std::string>());
  return keys;
}

BodyKind bodyKind(const ConfigNode& b) {
  const std::string k = b.choice("kind", {"carbody", "bogie", "wheel_hub", "tread", "wheel"});
  if (k == "carbody") return BodyKind::Carbody;
  if (k == "bogie") return BodyKind::Bogie;
  if (k == "wheel_hub") return BodyKind::WheelHub;
  if (k == "tread") return BodyKind::Tread;
  return BodyKind::Wheel;
}

/// A point attached to a body must lie on it: within its extent; a point body is where it is.
bool onBody(const BodySpec& b, double x_m) {
  const double tol = 1e-6;
  return x_m >= b.front_m - tol && x_m <= b.rear_m + tol;
}

std::string extentText(const BodySpec& b) {
  if (!b.hasPitch()) return "a point body at x = " + fmt(b.x_m) + " m";
  return "extends over [" + fmt(b.front_m) + ", " + fmt(b.rear_m) + "] m";
}

/// Lateral position of a body, element or pin: 0 = the centre line, > 0 one side (mirrored).
double lateralPosition(const ConfigNode& node) {
  const double y = node.number("y_m", Range::nonNegative(), 0.0);
  if (y > kMaxSideOffsetM) {
    node.fail("y_m", "lies " + fmt(y) + " m from the centre line, beyond " + fmt(kMaxSideOffsetM) +
                         " m: wider than rail vehicles are built (a slipped decimal point or unit?)");
  }
  return y;
}

int bodyRef(const ConfigNode& node, const std::string& key, const std::string& body_name, const VehicleParams& p) {
  const int b = p.bodyIndex(body_name);
  if (b < 0) {
    std::string known;
    for (const auto& body : p.bodies) known += (known.empty() ? "" : ", ") + body.name;
    node.fail(key, "no body '" + body_name + "' in this vehicle (bodies: " + known + ")");
  }
  return b;
}

void readBodies(const ConfigNode& v, VehicleParams& p) {
  const ConfigNode bodies = v.section("bodies");
  for (const std::string& name : keysOf(bodies)) {
    const ConfigNode b = bodies.section(name);
    BodySpec s;
    s.name = name;
    s.kind = bodyKind(b);
    s.x_m = b.number("x_m", vehicleBodyPositionRange());
    s.y_m = lateralPosition(b);
    s.mass_kg = b.number("mass_kg", Range::positive());
    if (b.has("roll_inertia_kg_m2")) {
      if (!s.onCentreLine()) {
        b.fail("roll_inertia_kg_m2",
               "a body of one side has no roll: its mass acts at its lateral position y_m (the full-width model "
               "mirrors it to -y_m)");
      }
      s.roll_inertia_kg_m2 = b.number("roll_inertia_kg_m2", Range::positive());
    } else if (p.fullWidth() && s.onCentreLine()) {
      b.fail("roll_inertia_kg_m2",
             "missing: the full-width vehicle (track.width: full) rolls, and a body on the centre line needs its "
             "roll inertia about the longitudinal axis through its centre of mass");
    }
    if (s.hasPitch()) {
      s.pitch_inertia_kg_m2 = b.number("pitch_inertia_kg_m2", Range::positive());
      const std::vector<double> ext = b.numbers("extent_m", Range::closed(-100.0, 200.0), 2, 2);
      s.front_m = ext[0];
      s.rear_m = ext[1];
      if (!(s.front_m <= s.x_m && s.x_m <= s.rear_m && s.front_m < s.rear_m)) {
        b.fail("extent_m",
               "must be [front, rear] behind the front axle, front < rear, around the centre of mass x_m = " +
                   fmt(s.x_m) + " m");
      }
    } else {
      for (const char* key : {"pitch_inertia_kg_m2", "extent_m"}) {
        if (b.has(key)) b.fail(key, "a " + b.text("kind") + " is a point body: it bounces but does not pitch");
      }
      s.front_m = s.rear_m = s.x_m;
    }
    p.bodies.push_back(s);
  }
  if (p.bodies.empty()) bodies.fail("", "a vehicle needs bodies");
}

void readSuspensions(const ConfigNode& v, VehicleParams& p) {
  const ConfigNode stages = v.section("suspension_stages");
  struct Stage {
    double k, d;
  };
  std::vector<std::pair<std::string, Stage>> stage_list;
  for (const std::string& name : keysOf(stages)) {
    const ConfigNode s = stages.section(name);
    stage_list.push_back(
        {name, {s.number("stiffness_n_m", Range::positive()), s.number("damping_n_s_m", Range::nonNegative())}});
  }
  for (const ConfigNode& e : v.sectionList("suspensions")) {
    SuspensionSpec s;
    s.stage = e.text("stage");
    const auto it =
        std::find_if(stage_list.begin(), stage_list.end(), [&](const auto& st) { return st.first == s.stage; });
    if (it == stage_list.end()) e.fail("stage", "no such stage in " + stages.keyPath());
    s.stiffness_n_m = it->second.k;
    s.damping_n_s_m = it->second.d;
    s.upper_body = bodyRef(e, "upper", e.text("upper"), p);
    s.lower_body = bodyRef(e, "lower", e.text("lower"), p);
    if (s.upper_body == s.lower_body) e.fail("lower", "an element joins two different bodies");
    s.x_m = e.number("x_m", vehicleBodyPositionRange());
    s.y_m = lateralPosition(e);
    for (int b : {s.upper_body, s.lower_body}) {
      const BodySpec& body = p.bodies[static_cast<size_t>(b)];
      if (!onBody(body, s.x_m)) {
        e.fail("x_m", "the element is attached outside body '" + body.name + "', which " + extentText(body));
      }
      if (s.y_m == 0.0 && !body.onCentreLine()) {
        e.fail("y_m", "an element on the centre line (y = 0) cannot hold body '" + body.name +
                          "' of one side (y = " + fmt(body.y_m) + " m)");
      }
      if (!body.onCentreLine() && std::abs(s.y_m - body.y_m) > 1e-6) {
        e.fail("y_m", "the element is attached beside body '" + body.name + "' (y = " + fmt(body.y_m) +
                          " m): a body of one side has no roll, its elements act at its lateral position");
      }
    }
    p.suspensions.push_back(s);
  }
}

void readJoints(const ConfigNode& v, VehicleParams& p) {
  if (!v.has("joints")) return;
  for (const ConfigNode& j : v.sectionList("joints")) {
    JointSpec s;
    j.choice("type", {"vertical_pin"});
    const std::vector<std::string> names = j.texts("bodies");
    if (names.size() != 2) j.fail("bodies", "a pin joins two bodies: [first, second]");
    s.body_a = bodyRef(j, "bodies", names[0], p);
    s.body_b = bodyRef(j, "bodies", names[1], p);
    s.name = j.text("name", names[0] + "/" + names[1]);
    if (s.body_a == s.body_b) j.fail("bodies", "a pin joins two different bodies");
    s.x_m = j.number("x_m", vehicleBodyPositionRange());
    s.y_m = lateralPosition(j);
    if (p.fullWidth() && s.y_m != 0.0) {
      j.fail("y_m",
             "the full-width vehicle (track.width: full) takes pins on the centre line: a pin of one side and its "
             "mirror image would close a chain of joints");
    }
    for (int b : {s.body_a, s.body_b}) {
      const BodySpec& body = p.bodies[static_cast<size_t>(b)];
      if (!body.hasPitch()) j.fail("bodies", "a pin joins carbodies or bogies; '" + body.name + "' is a point body");
      if (!onBody(body, s.x_m))
        j.fail("x_m", "the pin lies outside body '" + body.name + "', which " + extentText(body));
      if (p.fullWidth() && !body.onCentreLine()) {
        j.fail("bodies", "the full-width vehicle (track.width: full) pins bodies on the centre line; '" + body.name +
                             "' is a body of one side");
      }
    }
    s.pitch_stiffness_n_m_rad = j.number("pitch_stiffness_n_m_rad", Range::nonNegative());
    s.pitch_damping_n_m_s_rad = j.number("pitch_damping_n_m_s_rad", Range::nonNegative());
    // A vertical pin on the centre line leaves the relative roll free: full width only, optional.
    s.roll_stiffness_n_m_rad = j.number("roll_stiffness_n_m_rad", Range::nonNegative(), 0.0);
    s.roll_damping_n_m_s_rad = j.number("roll_damping_n_m_s_rad", Range::nonNegative(), 0.0);
    p.joints.push_back(s);
  }
}

void readWheels(const ConfigNode& v, VehicleParams& p) {
  const std::vector<ConfigNode> wheels = v.sectionList("wheels");
  if (wheels.empty()) v.fail("wheels", "a vehicle needs at least one wheel");
  for (const ConfigNode& w : wheels) {
    WheelSpec s;
    s.name = w.text("name");
    s.body = bodyRef(w, "body", w.text("body"), p);
    const BodySpec& body = p.bodies[static_cast<size_t>(s.body)];
    if (body.kind != BodyKind::Tread && body.kind != BodyKind::Wheel) {
      w.fail("body", "the contact is carried by a tread or a wheel, not by '" + body.name + "'");
    }
    // A wheel of one side stands on its rail (a centre-line wheelset touches both at +-rail_offset_m).
    if (!body.onCentreLine() && std::abs(body.y_m - p.rail_offset_m) > kWheelOnRailToleranceM) {
      v.section("bodies").section(body.name).fail(
          "y_m", "carries wheel " + s.name + " but is not on its rail: the rails lie at +-" + fmt(p.rail_offset_m) +
                     " m (site.rail_gauge_m / 2), within " + fmt(kWheelOnRailToleranceM * 1e3) + " mm");
    }
    for (const WheelSpec& other : p.wheels) {
      if (other.body == s.body) w.fail("body", "body '" + body.name + "' already carries wheel " + other.name);
    }
    s.type = w.choice("type", {"motor", "trailer"}) == "motor" ? AxleType::Motor : AxleType::Trailer;
    s.radius_m = w.number("radius_m", Range::closed(0.1, 1.0));
    p.wheels.push_back(s);
  }
  const std::vector<double> x = p.axleOffsets();
  if (x.front() != 0.0) {
    wheels.front().fail("body",
                        "the first wheel is the front axle, the origin of every offset: its body must be at "
                        "x_m = 0, not " +
                            fmt(x.front()) + " m");
  }
  for (size_t i = 1; i < x.size(); ++i) {
    if (!(x[i] > x[i - 1])) {
      wheels[i].fail("body", "wheels are listed front to rear: wheel " + std::to_string(i) + " at x = " + fmt(x[i]) +
                                 " m is not behind wheel " + std::to_string(i - 1) + " at " + fmt(x[i - 1]) + " m");
    }
  }
}

/// Resilient wheels (issue 33), `resilient_wheels` of the vehicle's entry: absent or `enabled: false`
/// leaves the file's vehicle as it is (its values are validated all the same, so switching it on
/// cannot meet a bad one). A rigid wheel body carrying a contact becomes the hub (kind wheel_hub, its
/// mass less its treads') and a tread per rail (kind tread, `<wheel>_tread`, right after the hub in
/// the body order) on a resilient ring (stage kResilientWheelStage, attached at the tread's point,
/// listed after the hub's own element); the contact moves to the tread. This is the T2000 motor
/// wheel's structure (the paper's appendix: tread m_t on the ring k_t, d_t under the hub), so the
/// same model, modes and passage serve it. A centre-line wheelset gets two treads, one per rail at
/// +-rail_offset_m, its roll inertia less theirs (2 m_t a^2). Wheels that already have a ring (a
/// tread hung from one element) get the section's ring stiffness and damping with `wheels:
/// resilient | all`; their tread keeps the file's mass.
void applyResilientWheels(const ConfigNode& v, VehicleParams& p) {
  if (!v.has("resilient_wheels")) return;
  const ConfigNode r = v.section("resilient_wheels");
  const bool enabled = r.flag("enabled", true);
  ResilientWheelParams rw;
  const std::string set = r.choice("wheels", {"rigid", "resilient", "all"}, "rigid");
  rw.wheels = set == "rigid"       ? ResilientWheelSet::Rigid
              : set == "resilient" ? ResilientWheelSet::Resilient
                                   : ResilientWheelSet::All;
  rw.stiffness_n_m = r.number("stiffness_n_m", kResilientRingStiffnessNM);
  rw.damping_n_s_m = r.number("damping_n_s_m", kResilientRingDampingNSM);
  const bool make_resilient = rw.wheels != ResilientWheelSet::Resilient;
  const bool respring = rw.wheels != ResilientWheelSet::Rigid;
  if (make_resilient) {
    rw.tread_mass_kg = r.number("tread_mass_kg", Range::positive());
  } else if (r.has("tread_mass_kg")) {
    r.fail("tread_mass_kg",
           "wheels: resilient changes the rings already fitted, whose treads are bodies of the file (their mass_kg "
           "is set there); a tread mass is for the rigid wheels made resilient (wheels: rigid | all)");
  }
  // Which wheels it acts on and whether their masses allow it, checked enabled or not; what depends on
  // where the wheels stand (a wheelset on the centre line gets two treads, its roll inertia) only when it
  // is applied: a misspelt position key would change it before the unknown-key check could name the key.
  std::vector<size_t> rigid, ringed;
  std::vector<int> ring_of(p.wheels.size(), -1);
  for (size_t w = 0; w < p.wheels.size(); ++w) {
    const int b = p.wheels[w].body;
    const BodySpec& body = p.bodies[static_cast<size_t>(b)];
    if (body.kind == BodyKind::Wheel) {
      rigid.push_back(w);
      if (!make_resilient) continue;
      // a wheelset on the centre line gets a tread on each rail (disabled: one tread, whatever the position)
      const double treads = enabled && body.onCentreLine() ? 2.0 : 1.0;
      if (!(treads * rw.tread_mass_kg < body.mass_kg)) {
        r.fail("tread_mass_kg",
               fmt(rw.tread_mass_kg) + " kg must lie below the mass of the wheel it is cut from: " + body.name +
                   " (wheel " + p.wheels[w].name + ") weighs " + fmt(body.mass_kg) + " kg" +
                   (treads > 1.0 ? ", a wheelset with a tread on each rail, so (0, " + fmt(0.5 * body.mass_kg) + ") kg"
                                 : ", so (0, " + fmt(body.mass_kg) + ") kg"));
      }
      const double tread_roll = treads * rw.tread_mass_kg * p.rail_offset_m * p.rail_offset_m;
      if (enabled && body.roll_inertia_kg_m2 > 0.0 && !(tread_roll < body.roll_inertia_kg_m2)) {
        r.fail("tread_mass_kg", "the treads of " + body.name + " at +-" + fmt(p.rail_offset_m) + " m would hold " +
                                    fmt(tread_roll) + " kg m^2 of its roll inertia, " + fmt(body.roll_inertia_kg_m2) +
                                    " kg m^2 (roll_inertia_kg_m2): too heavy");
      }
    } else {
      // a tread carrying the contact: its ring is the one element that holds it
      int count = 0;
      for (size_t e = 0; e < p.suspensions.size(); ++e) {
        const SuspensionSpec& el = p.suspensions[e];
        if (el.lower_body == b || el.upper_body == b) {
          ring_of[w] = static_cast<int>(e);
          ++count;
        }
      }
      if (count != 1) {
        r.fail("wheels", "tread " + body.name + " hangs on " + std::to_string(count) +
                             " elements: the ring of a resilient wheel is the one element that holds its tread");
      }
      ringed.push_back(w);
    }
  }
  if (make_resilient && !respring && rigid.empty()) {
    r.fail("wheels",
           "'rigid': this vehicle has no rigid wheel (every contact is on a tread); 'resilient' changes "
           "the rings it has");
  }
  if (respring && !make_resilient && ringed.empty()) {
    r.fail("wheels",
           "'resilient': this vehicle has no resilient wheel whose ring could change; 'rigid' or 'all' "
           "makes its rigid wheels resilient");
  }
  if (!enabled) return;
  p.resilient_wheels = rw;
  if (respring) {
    for (size_t w : ringed) {
      SuspensionSpec& ring = p.suspensions[static_cast<size_t>(ring_of[w])];
      ring.stiffness_n_m = rw.stiffness_n_m;
      ring.damping_n_s_m = rw.damping_n_s_m;
    }
  }
  if (!make_resilient || rigid.empty()) return;
  // New body order: each tread right after its hub; every index is remapped.
  std::vector<bool> converts(p.bodies.size(), false);
  for (size_t w : rigid) converts[static_cast<size_t>(p.wheels[w].body)] = true;
  std::vector<BodySpec> bodies;
  std::vector<int> new_index(p.bodies.size(), -1), tread_of(p.bodies.size(), -1);
  for (size_t b = 0; b < p.bodies.size(); ++b) {
    BodySpec hub = p.bodies[b];
    new_index[b] = static_cast<int>(bodies.size());
    if (!converts[b]) {
      bodies.push_back(hub);
      continue;
    }
    BodySpec tread;
    tread.name = hub.name + "_tread";
    if (p.bodyIndex(tread.name) >= 0) {
      r.fail("wheels", "the tread of " + hub.name + " would be called " + tread.name +
                           ", the name of a body of the file already");
    }
    tread.kind = BodyKind::Tread;
    tread.x_m = hub.x_m;
    tread.y_m = hub.onCentreLine() ? p.rail_offset_m : hub.y_m;
    tread.mass_kg = rw.tread_mass_kg;
    tread.front_m = tread.rear_m = tread.x_m;
    const double treads = hub.onCentreLine() ? 2.0 : 1.0;
    hub.kind = BodyKind::WheelHub;
    hub.mass_kg -= treads * rw.tread_mass_kg;
    if (hub.roll_inertia_kg_m2 > 0.0)
      hub.roll_inertia_kg_m2 -= treads * rw.tread_mass_kg * p.rail_offset_m * p.rail_offset_m;
    bodies.push_back(hub);
    tread_of[b] = static_cast<int>(bodies.size());
    bodies.push_back(tread);
  }
  std::vector<SuspensionSpec> elements;
  for (size_t e = 0; e < p.suspensions.size(); ++e) {
    SuspensionSpec el = p.suspensions[e];
    const int old_lower = el.lower_body;
    el.upper_body = new_index[static_cast<size_t>(el.upper_body)];
    el.lower_body = new_index[static_cast<size_t>(el.lower_body)];
    elements.push_back(el);
    // the ring after the last element that holds the hub from above
    const bool last_above = std::none_of(p.suspensions.begin() + static_cast<long>(e) + 1, p.suspensions.end(),
                                         [&](const SuspensionSpec& o) { return o.lower_body == old_lower; });
    if (tread_of[static_cast<size_t>(old_lower)] >= 0 && last_above) {
      const BodySpec& tread = bodies[static_cast<size_t>(tread_of[static_cast<size_t>(old_lower)])];
      SuspensionSpec ring;
      ring.stage = kResilientWheelStage;
      ring.upper_body = el.lower_body;
      ring.lower_body = tread_of[static_cast<size_t>(old_lower)];
      ring.x_m = tread.x_m;
      ring.y_m = tread.y_m;
      ring.stiffness_n_m = rw.stiffness_n_m;
      ring.damping_n_s_m = rw.damping_n_s_m;
      elements.push_back(ring);
    }
  }
  for (size_t b = 0; b < p.bodies.size(); ++b) {
    if (converts[b] && std::none_of(p.suspensions.begin(), p.suspensions.end(),
                                    [&](const SuspensionSpec& o) { return o.lower_body == static_cast<int>(b); })) {
      r.fail("wheels", "wheel body " + p.bodies[b].name +
                           " hangs from no element: a resilient wheel's hub rests on a suspension");
    }
  }
  for (JointSpec& j : p.joints) {
    j.body_a = new_index[static_cast<size_t>(j.body_a)];
    j.body_b = new_index[static_cast<size_t>(j.body_b)];
  }
  for (WheelSpec& w : p.wheels) {
    const auto b = static_cast<size_t>(w.body);
    w.body = converts[b] ? tread_of[b] : new_index[b];
  }
  p.bodies = std::move(bodies);
  p.suspensions = std::move(elements);
}

/// Every body must be held (through elements and joints) by a wheel, and every wheel must lie
/// under the vehicle's carbodies. (A wheel within its bogie follows from its elements: each is
/// attached to both its bodies, readSuspensions.)
void checkStructure(const ConfigNode& v, const VehicleParams& p) {
  const size_t n = p.bodies.size();
  std::vector<bool> held(n, false);
  for (const WheelSpec& w : p.wheels) held[static_cast<size_t>(w.body)] = true;
  for (bool grew = true; grew;) {
    grew = false;
    auto link = [&](int a, int b) {
      if (held[static_cast<size_t>(a)] != held[static_cast<size_t>(b)]) {
        held[static_cast<size_t>(a)] = held[static_cast<size_t>(b)] = true;
        grew = true;
      }
    };
    for (const SuspensionSpec& e : p.suspensions) link(e.upper_body, e.lower_body);
    for (const JointSpec& j : p.joints) link(j.body_a, j.body_b);
  }
  std::string loose;
  for (size_t b = 0; b < n; ++b) {
    if (!held[b]) loose += (loose.empty() ? "" : ", ") + p.bodies[b].name;
  }
  if (!loose.empty()) {
    v.fail("bodies",
           "disconnected: no element or joint links " + loose + " to a wheel (every body must rest on the rail)");
  }
  double front = 1e300, rear = -1e300;
  for (const BodySpec& b : p.bodies) {
    if (b.kind != BodyKind::Carbody) continue;
    front = std::min(front, b.front_m);
    rear = std::max(rear, b.rear_m);
  }
  for (const WheelSpec& w : p.wheels) {
    const BodySpec& body = p.bodies[static_cast<size_t>(w.body)];
    if (front <= rear && (body.x_m < front || body.x_m > rear)) {
      v.fail("wheels", "wheel " + w.name + " at x = " + fmt(body.x_m) + " m lies outside the carbodies, [" +
                           fmt(front) + ", " + fmt(rear) + "] m behind the front axle");
    }
  }
}

}  // namespace

std::vector<std::string> vehicleLibrary(const ConfigNode& root) { return keysOf(root.section("vehicles")); }

VehicleParams loadVehicleParams(const ConfigNode& root, const std::string& name) {
  VehicleParams p;
  if (root.has("vehicle")) {
    const ConfigNode sel = root.section("vehicle");
    // 1 = the whole vehicle on one rail (a sensitivity study), 0.5 = the symmetric half.
    p.body_share_per_rail = sel.section("half_vehicle").number("body_share_per_rail", Range{0.0, 1.0, true, false});
    p.gravity_m_s2 = sel.number("gravity_m_s2", Range::closed(9.0, 10.0), 9.81);
  }
  // The vehicle has the track's width (one switch for the chain: a half vehicle on both rails, or a
  // full one on one rail, has no meaning); the rails' lateral position is the site's gauge.
  if (root.has("track")) p.width = track::loadTrackParams(root).width;
  if (root.has("site")) p.rail_offset_m = loadSiteLayout(root).exterior_rail_y_m;
  const ConfigNode library = root.section("vehicles");
  if (!library.has(name)) {
    std::string known;
    for (const auto& k : keysOf(library)) known += (known.empty() ? "" : ", ") + k;
    library.fail(name, "no vehicle '" + name + "' in the library (vehicles: " + known + ")");
  }
  const ConfigNode v = library.section(name);
  p.name = name;
  p.description = v.text("description", name);
  p.hertz_constant_n_m1_5 = v.section("contact").number("hertz_constant_n_m1_5", Range::positive());
  readBodies(v, p);
  readSuspensions(v, p);
  readJoints(v, p);
  readWheels(v, p);
  applyResilientWheels(v, p);
  checkStructure(v, p);
  try {
    const VehicleModel model(p);
  } catch (const std::invalid_argument& e) {
    v.fail("bodies", e.what());
  }
  return p;
}

VehicleParams loadVehicleParams(const ConfigNode& root) {
  const ConfigNode sel = root.section("vehicle");
  return loadVehicleParams(root, sel.choice("name", vehicleLibrary(root)));
}

UnevennessParams loadUnevennessParams(const ConfigNode& root) {
  UnevennessParams u;
  const ConfigNode un = root.section("unevenness");
  const ConfigNode d = un.section("defect");
  u.defect.enabled = d.flag("enabled");
  u.defect.position_m = d.number("position_m", Range::open(-1.0e5, 1.0e5));
  u.defect.height_m = d.number("height_m", Range::closed(0.0, 0.05));
  u.defect.length_m = d.number("length_m", Range::closed(0.0, 1.0));
  if (root.has("track")) u.width = track::loadTrackParams(root).width;
  const std::string rails = d.choice("rails", {"both", "left", "right"}, "both");
  u.defect.rails = rails == "left" ? DefectRails::Left : rails == "right" ? DefectRails::Right : DefectRails::Both;
  if (u.defect.rails != DefectRails::Both && u.width == track::TrackWidth::Half) {
    d.fail("rails", "'" + rails +
                        "': the half track (track.width: half) is the symmetric special case, its one rail stands "
                        "for both rails alike; a defect on one rail needs track.width: full");
  }
  if (u.defect.enabled && root.has("track")) {
    const TrackLayout track = loadTrackLayout(root);
    const double x0 = track.x_min_m;
    const double x1 = track.x_max_m;
    if (u.defect.position_m < x0 || u.defect.position_m + u.defect.length_m > x1) {
      d.fail("position_m", "the defect [" + fmt(u.defect.position_m) + ", " +
                               fmt(u.defect.position_m + u.defect.length_m) + "] m lies outside the modelled track [" +
                               fmt(x0) + ", " + fmt(x1) + "] m (track.extent)");
    }
  }
  if (un.has("random")) {
    const ConfigNode r = un.section("random");
    auto& p = u.random;
    p.enabled = r.flag("enabled");
    p.psd = r.choice("psd", {"fra", "power_law"}, "fra");
    p.fra_a_m2_rad_m = r.number("fra_a_m2_rad_m", Range::positive(), p.fra_a_m2_rad_m);
    p.fra_cutoff_rad_m = r.number("fra_cutoff_rad_m", Range::positive(), p.fra_cutoff_rad_m);
    p.fra_k = r.number("fra_k", Range::positive(), p.fra_k);
    p.power_law_a_m3_rad = r.number("power_law_a_m3_rad", Range::positive(), p.power_law_a_m3_rad);
    p.power_law_ref_rad_m = r.number("power_law_ref_rad_m", Range::positive(), p.power_law_ref_rad_m);
    p.power_law_exponent = r.number("power_law_exponent", Range::closed(0.0, 6.0), p.power_law_exponent);
    p.min_wavelength_m = r.number("min_wavelength_m", Range::positive(), p.min_wavelength_m);
    p.max_wavelength_m = r.number("max_wavelength_m", Range::positive(), p.max_wavelength_m);
    if (p.max_wavelength_m <= p.min_wavelength_m) r.fail("max_wavelength_m", "must exceed min_wavelength_m");
    p.component_count = static_cast<int>(r.integer("component_count", 1, 100000, p.component_count));
    p.seed = static_cast<unsigned long>(r.integer("seed", 0, 2147483647L, static_cast<long>(p.seed)));
    p.grid_spacing_m = r.number("grid_spacing_m", Range::closed(1e-4, 0.1), p.grid_spacing_m);
    p.coherence = r.number("coherence", Range::closed(0.0, 1.0), p.coherence);
    p.coherence_decay_m_rad = r.number("coherence_decay_m_rad", Range::closed(0.0, 100.0), p.coherence_decay_m_rad);
  }
  if (un.has("measured_profile")) {
    const ConfigNode m = un.section("measured_profile");
    u.measured.enabled = m.flag("enabled");
    if (u.measured.enabled) {
      u.measured.file = m.filePath("file");
      std::error_code ec;
      if (!std::filesystem::is_regular_file(u.measured.file, ec)) {
        m.fail("file", "no such file: " + u.measured.file + " (a path is relative to the file that sets it)");
      }
    } else if (m.has("file")) {
      m.text("file");  // kept for when the profile is enabled again: still a file name
    }
    u.measured.scale = m.number("scale", Range::closed(-1.0e3, 1.0e3), 1.0);
    u.measured.max_abs_m = loadStreamLimits(root).unevenness_m;
  }
  return u;
}

PassageParams loadPassageParams(const ConfigNode& root) {
  const ConfigNode s = root.section("simulation");
  PassageParams p;
  p.vehicle_track = s.choice("vehicle_track", {"flexible", "rigid"}, "flexible") == "rigid" ? VehicleTrack::Rigid
                                                                                            : VehicleTrack::Flexible;
  const PassageSpan span = loadPassageSpan(root);
  p.speed_m_s = span.speed_m_s;
  p.duration_s = span.duration_s;
  // Newmark beta=1/4 is unconditionally stable; accuracy limits dt: the
  // stiffest vehicle mode (tread on the Hertz spring, ~600 Hz) needs >= 20
  // steps per period and the defect (~7 ms at 30 km/h) >= 100 steps.
  p.time_step_s = s.number("time_step_s", Range::closed(1.0e-7, 5.0e-5));
  p.front_axle_start_m = span.front_axle_start_m;
  p.contact_tolerance = s.number("contact_tolerance", Range::closed(1e-14, 1e-4), p.contact_tolerance);
  p.convected_track_start = s.flag("convected_track_start", false);
  return p;
}

}  // namespace railvib::vehicle
