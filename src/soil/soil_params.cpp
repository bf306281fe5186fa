#include "railvib/soil/soil_params.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "railvib/common/machine.hpp"
#include "railvib/common/names.hpp"

namespace railvib::soil {

namespace {

// Where the house's footprint receivers come from (their origin), to find them again.
constexpr const char* kFootprintOrigin = "building.footprint";

Material readMaterial(const ConfigNode& n) {
  Material m;
  m.young_modulus_pa = n.number("young_modulus_pa", Range::open(0.0, 1e13));
  m.density_kg_m3 = n.number("density_kg_m3", Range::open(0.0, 1e5));
  // nu >= 0.5 is incompressible (no finite P-wave speed); explicit FE needs nu < 0.5.
  m.poisson_ratio = n.number("poisson_ratio", Range{-1.0, 0.5, true, true});
  return m;
}

// soil.layers, soil.half_space, soil.rayleigh_beta_s, soil.damping.
void readProfileAndDamping(const ConfigNode& soil, SoilParams& p) {
  for (const ConfigNode& l : soil.sectionList("layers")) {
    Layer layer;
    layer.thickness_m = l.number("thickness_m", Range::open(0.0, 1e4));
    layer.material = readMaterial(l);
    p.profile.push_back(layer);
  }
  Layer hs;
  hs.material = readMaterial(soil.section("half_space"));
  p.profile.push_back(hs);
  p.solver.rayleigh_beta_s = soil.number("rayleigh_beta_s", Range{0.0, 1.0, false, true});
  if (soil.has("damping")) {
    const ConfigNode d = soil.section("damping");
    p.solver.damping_cutoff_hz = d.number("filter_cutoff_hz", Range::open(0.0, 1e5), 300.0);
  }
}

// soil.mesh.f_max_hz: the highest frequency the mesh resolves.
double meshFrequency(const ConfigNode& mesh) { return mesh.number("f_max_hz", Range::open(0.0, 1e4), 60.0); }

void readMeshResolution(const ConfigNode& mesh, SoilParams& p);

// soil.mesh: the box, resolution, precision, threads, memory cap.
void readMesh(const ConfigNode& mesh, SoilParams& p) {
  p.mesh.f_max_hz = meshFrequency(mesh);
  p.mesh.elements_per_wavelength = mesh.number("elements_per_wavelength", Range::closed(4.0, 100.0), 8.0);
  p.mesh.depth_m = mesh.number("depth_m", Range::open(0.0, 1e5));
  // The plan of the box: given (mode fixed, the default), or fitted to the site later (fitBoxToSite).
  const ConfigNode extent = mesh.has("extent") ? mesh.section("extent") : mesh;
  p.box_fitted = mesh.has("extent") && extent.choice("mode", {"fixed", "auto"}) == "auto";
  if (p.box_fitted) {
    // Bounds for mode fixed may stay (a --set switches the mode): valid numbers, not used.
    for (const char* key : {"x_min_m", "x_max_m", "y_min_m", "y_max_m"}) {
      if (mesh.has(key)) mesh.number(key, Range::open(-1e5, 1e5));
    }
    p.box_margin_along_m = extent.number("margin_along_track_m", Range::closed(0.0, 1e4));
    p.box_margin_across_m = extent.number("margin_across_track_m", Range::closed(0.0, 1e4));
    return readMeshResolution(mesh, p);
  }
  if (mesh.has("extent")) {  // mode fixed: margins kept for a switch to auto, still valid values
    for (const char* key : {"margin_along_track_m", "margin_across_track_m"}) {
      if (extent.has(key)) extent.number(key, Range::closed(0.0, 1e4));
    }
  }
  p.mesh.x_min_m = mesh.number("x_min_m", Range::open(-1e5, 1e5));
  p.mesh.x_max_m = mesh.number("x_max_m", Range::open(-1e5, 1e5));
  p.mesh.y_min_m = mesh.number("y_min_m", Range::open(-1e5, 1e5));
  p.mesh.y_max_m = mesh.number("y_max_m", Range::open(-1e5, 1e5));
  if (!(p.mesh.x_max_m > p.mesh.x_min_m)) mesh.fail("x_max_m", "must be greater than x_min_m");
  if (!(p.mesh.y_max_m > p.mesh.y_min_m)) mesh.fail("y_max_m", "must be greater than y_min_m");
  readMeshResolution(mesh, p);
}

// soil.mesh: the element size cap, step, precision, threads, ranks, kernel, memory cap.
void readMeshResolution(const ConfigNode& mesh, SoilParams& p) {
  p.mesh.max_plane_size_m = mesh.number("max_plane_size_m", Range::nonNegative(), 0.0);
  p.solver.safety_factor = mesh.number("safety_factor", Range{0.0, 1.0, true, false}, 0.9);
  p.solver.precision =
      mesh.choice("precision", {"float", "double"}, "float") == "float" ? Precision::Float : Precision::Double;
  p.solver.threads = static_cast<int>(mesh.integer("threads", 0, 256, 0));
  p.solver.ranks = static_cast<int>(mesh.integer("ranks", 0, 4096, 0));
  p.solver.kernel = kernelFromName(mesh.choice("kernel", {"element", "stencil"}, "element"));
  p.max_memory_gb = mesh.number("max_memory_gb", Range::open(0.0, 1e4), 12.0);
  p.mesh.inclusion_snap_tolerance_m = mesh.number("inclusion_snap_tolerance_m", Range::open(0.0, 1e3), 0.25);
}

// soil.inclusions: boxes of their own material or voids (trenches, walls, a meshed foundation), in
// frame track (x along, y across towards the building) with depth_m [top, bottom] down from the surface.
void readInclusions(const ConfigNode& soil, SoilParams& p) {
  if (!soil.has("inclusions")) return;
  for (const ConfigNode& n : soil.sectionList("inclusions")) {
    InclusionSpec inc;
    inc.name = n.text("name");
    for (const InclusionSpec& other : p.mesh.inclusions) {
      if (other.name == inc.name) n.fail("name", "'" + inc.name + "' names two inclusions");
    }
    inc.is_void = n.choice("kind", {"void", "material"}) == "void";
    const std::vector<double> x = n.numbers("x_m", Range::open(-1e5, 1e5), 2, 2);
    const std::vector<double> y = n.numbers("y_m", Range::open(-1e5, 1e5), 2, 2);
    const std::vector<double> d = n.numbers("depth_m", Range::closed(0.0, 1e5), 2, 2);
    if (!(x[1] > x[0])) n.fail("x_m", "the second value (the box's end) must exceed the first");
    if (!(y[1] > y[0])) n.fail("y_m", "the second value (the box's far side) must exceed the first");
    if (!(d[1] > d[0])) n.fail("depth_m", "the second value (the bottom) must be deeper than the first (the top)");
    inc.x_min_m = x[0], inc.x_max_m = x[1], inc.y_min_m = y[0], inc.y_max_m = y[1];
    inc.top_m = d[0], inc.bottom_m = d[1];
    if (!inc.is_void) {
      const ConfigNode m = n.section("material");
      inc.material = readMaterial(m);
      inc.rayleigh_beta_s = m.number("rayleigh_beta_s", Range{0.0, 1.0, false, true}, -1.0);
      inc.implicit = n.choice("integration", {"explicit", "implicit"}, "explicit") == "implicit";
      // An implicit inclusion's damping is integrated in its own solve (docs/soil.md, "Implicit
      // inclusions"): its own coefficient, 0 (undamped) when left out, needs no soil filter.
      if (inc.implicit && inc.rayleigh_beta_s < 0.0) inc.rayleigh_beta_s = 0.0;
      if (!inc.implicit && inc.rayleigh_beta_s >= 0.0 && inc.rayleigh_beta_s != p.solver.rayleigh_beta_s &&
          !(p.solver.rayleigh_beta_s > 0.0)) {
        m.fail("rayleigh_beta_s",
               "an inclusion's own Rayleigh coefficient needs the soil's damping filter "
               "(soil.rayleigh_beta_s > 0); leave it out to take the soil's");
      }
    }
    p.mesh.inclusions.push_back(inc);
  }
}

// The boundary's absorbing zone (e.g. a graded layer): receivers and loads stay out of it.
struct AbsorbingZone {
  double thickness_m = 0.0;
  bool bottom = false;
  std::string key;  // soil.boundary.<method>
};

AbsorbingZone absorbingZone(const SolverOptions& s) {
  const std::unique_ptr<SoilBoundary> boundary = makeSoilBoundary(s.boundary);
  return {boundary->zoneThicknessM(), boundary->zoneAlongBottom(), boundaryMethodName(s.boundary.method)};
}

// soil.mesh.extent mode auto: the box holds the site, every receiver (the sensors, the receiver
// line, the house's free-field and footprint points), the inclusions, the section plane and the
// track's sleepers across it, with margin_across_track_m beyond them on each side across the track
// and margin_along_track_m of loaded track beyond them along it, and the boundary's absorbing zone
// outside that (as track.extent mode auto fits the track to the run).
void fitBoxToSite(const ConfigNode& soil, SoilParams& p) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  auto hold = [&](double x_lo, double x_hi, double y_lo, double y_hi) {
    x0 = std::min(x0, x_lo), x1 = std::max(x1, x_hi), y0 = std::min(y0, y_lo), y1 = std::max(y1, y_hi);
  };
  for (const ReceiverSpec& r : p.receivers) hold(r.x_m, r.x_m, r.y_m, r.y_m);
  for (const InclusionSpec& inc : p.mesh.inclusions) hold(inc.x_min_m, inc.x_max_m, inc.y_min_m, inc.y_max_m);
  const ConfigNode out = soil.section("output");
  if (out.has("section") && out.section("section").flag("enabled", true)) {
    const double x = out.section("section").number("x_m", Range::open(-1e5, 1e5));
    hold(x, x, y0, y1);
  }
  if (!(x1 >= x0)) {
    soil.section("mesh").section("extent").fail("mode",
                                                "auto needs something to hold: no receiver, inclusion or "
                                                "section in the scenario");
  }
  // The sleepers' footprint across the track (the loads' width), centred on the track axis.
  hold(x0, x1, -0.5 * p.track.length_m, 0.5 * p.track.length_m);
  const double zone = absorbingZone(p.solver).thickness_m;
  p.mesh.x_min_m = x0 - p.box_margin_along_m - zone;
  p.mesh.x_max_m = x1 + p.box_margin_along_m + zone;
  p.mesh.y_min_m = y0 - p.box_margin_across_m - zone;
  p.mesh.y_max_m = y1 + p.box_margin_across_m + zone;
}

// soil.boundary: the method and its parameters; its absorbing zone must leave room in the box.
void checkBoundaryFits(const ConfigNode& b, const SoilParams& p) {
  const AbsorbingZone zone = absorbingZone(p.solver);
  const double layer = zone.thickness_m;
  if (layer > 0.0 && (2.0 * layer >= p.mesh.x_max_m - p.mesh.x_min_m ||
                      2.0 * layer >= p.mesh.y_max_m - p.mesh.y_min_m || (zone.bottom && layer >= p.mesh.depth_m))) {
    b.section(zone.key).fail("thickness_m", "the absorbing zone would fill the soil box");
  }
}

double receiverRate(const ConfigNode& output) {
  return output.number("receiver_rate_hz", Range::open(0.0, 1e6), 1000.0);
}

// soil.output rates, soil.loads.
void readOutputAndLoads(const ConfigNode& soil, SoilParams& p) {
  const ConfigNode out = soil.section("output");
  p.receiver_rate_hz = receiverRate(out);
  p.snapshot_rate_hz = out.number("snapshot_rate_hz", Range::open(0.0, 1e6), 100.0);
  const double ratio = p.receiver_rate_hz / p.snapshot_rate_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9 || ratio < 1.0) {
    out.fail("snapshot_rate_hz", "must divide receiver_rate_hz into an integer ratio >= 1");
  }
  p.snapshot_horizontal = out.choice("snapshot_components", {"all", "vertical"}, "all") == "all";
  p.solver.align_rate_hz = p.receiver_rate_hz;
  if (out.has("section")) {
    const ConfigNode section = out.section("section");
    p.section_enabled = section.flag("enabled", true);
    p.section_x_m = section.number("x_m", Range::open(p.mesh.x_min_m, p.mesh.x_max_m));
  }
  const ConfigNode loads = soil.section("loads");
  p.loads_outside_mesh = loads.choice("outside_mesh", {"error", "drop"}, "error");
  // Required with drop (where a load may go missing); validated if given with error.
  p.drop_min_receiver_distance_m = p.loads_outside_mesh == "drop"
                                       ? loads.number("drop_min_receiver_distance_m", Range::closed(0.0, 1.0e4))
                                       : loads.number("drop_min_receiver_distance_m", Range::closed(0.0, 1.0e4), 0.0);
  p.start_from_static = loads.flag("start_from_static", true);
}

void addPoints(const std::vector<NamedPoint>& points, const std::string& origin, SoilParams& p) {
  for (const NamedPoint& q : points) p.receivers.push_back({q.name, q.x_m, q.y_m, q.z_m, origin});
}

// Ground sensors, the line perpendicular to the track (soil.output.receiver_line), the house's.
void collectReceivers(const ConfigNode& root, const HouseReceivers& house, SoilParams& p) {
  const SiteLayout site = loadSiteLayout(root);
  // site.ground_sensors[i] or virtual_sensors.sensors[i]: where each was defined.
  for (const NamedPoint& q : site.ground_sensors) addPoints({q}, q.key, p);
  const ConfigNode out = root.section("soil").section("output");
  if (out.has("receiver_line")) {
    const ConfigNode line = out.section("receiver_line");
    const double x = line.number("x_m", Range::open(-1e5, 1e5));
    const double y0 = line.number("y_min_m", Range::open(-1e5, 1e5));
    const double y1 = line.number("y_max_m", Range::open(-1e5, 1e5));
    const double step = line.number("step_m", Range::open(0.0, 1e4));
    if (y1 < y0) line.fail("y_max_m", "must be >= y_min_m");
    if ((y1 - y0) / step > 10000.0) line.fail("step_m", "more than 10000 receivers on the line");
    const long n = static_cast<long>(std::floor((y1 - y0) / step + 1e-9));
    for (long i = 0; i <= n; ++i) {
      const double y = y0 + step * static_cast<double>(i);
      p.receivers.push_back({names::receiverLinePoint(y), x, y, 0.0, line.keyPath()});
    }
  }
  if (out.flag("building_receivers", true)) addPoints(house.free_field, "site.building", p);
  addPoints(house.footprint, kFootprintOrigin, p);
}

// Every receiver inside the box and outside its absorbing layer (there it would record damped motion).
void checkReceivers(const ConfigNode& soil, const SoilParams& p) {
  const AbsorbingZone zone = absorbingZone(p.solver);
  const double layer = zone.thickness_m;
  for (const ReceiverSpec& r : p.receivers) {
    const bool inside = r.x_m >= p.mesh.x_min_m && r.x_m <= p.mesh.x_max_m && r.y_m >= p.mesh.y_min_m &&
                        r.y_m <= p.mesh.y_max_m && r.z_m <= 0.0 && -r.z_m <= p.mesh.depth_m;
    if (!inside) {
      std::ostringstream why;
      why << "receiver '" << r.name << "' (from " << r.origin << ") at (" << r.x_m << ", " << r.y_m << ", " << r.z_m
          << ") m is outside the soil mesh box x [" << p.mesh.x_min_m << ", " << p.mesh.x_max_m << "], y ["
          << p.mesh.y_min_m << ", " << p.mesh.y_max_m << "], depth [0, " << p.mesh.depth_m << "] m";
      soil.section("mesh").fail("x_min_m", why.str());
    }
    const double dist = std::min({r.x_m - p.mesh.x_min_m, p.mesh.x_max_m - r.x_m, r.y_m - p.mesh.y_min_m,
                                  p.mesh.y_max_m - r.y_m, zone.bottom ? p.mesh.depth_m + r.z_m : 1e300});
    if (layer > 0.0 && dist < layer) {
      std::ostringstream why;
      why << "receiver '" << r.name << "' (from " << r.origin << ") at (" << r.x_m << ", " << r.y_m << ", " << r.z_m
          << ") m is " << dist << " m from the box face, inside the " << layer
          << " m absorbing zone of the boundary: enlarge soil.mesh or thin the zone";
      soil.section("boundary").section(zone.key).fail("thickness_m", why.str());
    }
  }
}

// Each inclusion snapped to the mesh (within the tolerance, at least an element thick), disjoint from
// the others, off the boundary; no void under the track's sleepers or at a receiver.
void checkInclusions(const ConfigNode& soil, const SoilParams& p, StructuredMesh& m, const SoilBoundary& boundary) {
  if (p.mesh.inclusions.empty()) return;
  const std::vector<ConfigNode> nodes = soil.sectionList("inclusions");
  for (size_t q = 0; q < p.mesh.inclusions.size(); ++q) {
    const InclusionSpec& spec = p.mesh.inclusions[q];
    try {
      addInclusions(m, {spec}, p.mesh.inclusion_snap_tolerance_m);
      StructuredMesh one = m;
      one.inclusions = {m.inclusions.back()};
      checkInclusionsInside(one, p.solver.absorbing, boundary);
    } catch (const InclusionError& e) {
      nodes[q].fail(e.axis().empty() ? "name" : e.axis() + "_m", e.what());
    }
    if (!spec.is_void) continue;
    const MeshInclusion& inc = m.inclusions.back();
    const double x0 = m.x(inc.elements.i0), x1 = m.x(inc.elements.i1);
    const double y0 = m.y(inc.elements.j0), y1 = m.y(inc.elements.j1);
    const double top = m.z[inc.elements.k0], bottom = m.z[inc.elements.k1];
    const double half_length = 0.5 * p.track.length_m;
    if (top == 0.0 && y0 < half_length && y1 > -half_length) {
      std::ostringstream why;
      why << "the void '" << spec.name << "' opens at the surface across y [" << y0 << ", " << y1
          << "] m as meshed, under the track's sleepers (|y| <= " << half_length
          << " m): a trench through the track carries no load";
      nodes[q].fail("y_m", why.str());
    }
    // The house stands on its footprint (the rectangle of its footprint points): no void under it.
    double hx0 = 1e300, hx1 = -1e300, hy0 = 1e300, hy1 = -1e300;
    for (const ReceiverSpec& r : p.receivers) {
      if (r.origin != kFootprintOrigin) continue;
      hx0 = std::min(hx0, r.x_m), hx1 = std::max(hx1, r.x_m), hy0 = std::min(hy0, r.y_m), hy1 = std::max(hy1, r.y_m);
    }
    if (hx1 >= hx0 && top == 0.0 && x0 < hx1 && x1 > hx0 && y0 < hy1 && y1 > hy0) {
      std::ostringstream why;
      why << "the void '" << spec.name << "' (x [" << x0 << ", " << x1 << "], y [" << y0 << ", " << y1
          << "] m as meshed) opens under the house's footprint (x [" << hx0 << ", " << hx1 << "], y [" << hy0 << ", "
          << hy1 << "] m): a trench through the house";
      nodes[q].fail("y_m", why.str());
    }
    for (const ReceiverSpec& r : p.receivers) {
      const double depth = -r.z_m;
      const bool in_void = r.x_m > x0 && r.x_m < x1 && r.y_m > y0 && r.y_m < y1 &&
                           (depth > top || (top == 0.0 && depth == 0.0)) && depth < bottom;
      if (in_void) {
        std::ostringstream why;
        why << "the void '" << spec.name << "' (x [" << x0 << ", " << x1 << "], y [" << y0 << ", " << y1 << "], depth ["
            << top << ", " << bottom << "] m as meshed) holds receiver '" << r.name << "' (from " << r.origin
            << ") at (" << r.x_m << ", " << r.y_m << ", " << r.z_m << ") m: no soil there to move";
        nodes[q].fail("y_m", why.str());
      }
    }
  }
}

// The boundary must fit the mesh, and the mesh soil.mesh.max_memory_gb: checked before anything is allocated.
void checkMemory(const ConfigNode& soil, const SoilParams& p) {
  const ConfigNode mesh = soil.section("mesh");
  StructuredMesh m;
  MeshSpec plain = p.mesh;
  plain.inclusions.clear();
  try {
    m = buildMesh(p.profile, plain);
  } catch (const std::invalid_argument& e) {
    mesh.fail("f_max_hz", e.what());
  }
  // The boundary on this mesh (e.g. a PML must be at least one element thick).
  const std::unique_ptr<SoilBoundary> boundary = makeSoilBoundary(p.solver.boundary);
  try {
    boundary->kernelElements(BoundaryContext{&m, nullptr, p.solver.absorbing});
  } catch (const std::invalid_argument& e) {
    soil.section("boundary").section(absorbingZone(p.solver).key).fail("thickness_m", e.what());
  }
  checkInclusions(soil, p, m, *boundary);
  const double bytes = static_cast<double>(solverMemoryBytes(m, p.solver.precision)) +
                       static_cast<double>(m.nodeCount()) * sizeof(double) +
                       static_cast<double>((m.nx + 1) * (m.ny + 1)) * 3.0 * sizeof(double);
  if (bytes > p.max_memory_gb * 1e9) {
    std::ostringstream why;
    why << "the mesh (" << m.nx << " x " << m.ny << " x " << m.nz << " = " << m.elementCount() << " elements) needs "
        << bytes / 1e9 << " GB, more than max_memory_gb = " << p.max_memory_gb
        << " GB: lower f_max_hz / elements_per_wavelength or shrink the box";
    mesh.fail("max_memory_gb", why.str());
  }
  // max_memory_gb is the user's cap; the machine's memory is the hard one.
  const double machine = machineMemoryBytes();
  if (machine > 0.0 && bytes > machine) {
    std::ostringstream why;
    why << "the mesh (" << m.elementCount() << " elements) needs " << bytes / 1e9 << " GB, more than the "
        << machine / 1e9 << " GB of memory of this machine (MemTotal or the cgroup limit), whatever max_memory_gb "
        << "allows: lower f_max_hz / elements_per_wavelength or shrink the box";
    mesh.fail("max_memory_gb", why.str());
  }
}

}  // namespace

double loadReceiverRateHz(const ConfigNode& root) { return receiverRate(root.section("soil").section("output")); }

double loadResolvedFrequencyHz(const ConfigNode& root) { return meshFrequency(root.section("soil").section("mesh")); }

SoilParams loadSoilParams(const ConfigNode& root, const HouseReceivers& house) {
  SoilParams p;
  const ConfigNode soil = root.section("soil");
  readProfileAndDamping(soil, p);
  readMesh(soil.section("mesh"), p);
  p.solver.boundary = loadBoundarySpec(soil.section("boundary"));
  readInclusions(soil, p);
  p.track = loadTrackLayout(root);
  collectReceivers(root, house, p);
  if (p.box_fitted) fitBoxToSite(soil, p);
  checkBoundaryFits(soil.section("boundary"), p);
  readOutputAndLoads(soil, p);
  checkReceivers(soil, p);
  checkMemory(soil, p);
  return p;
}

}  // namespace railvib::soil
