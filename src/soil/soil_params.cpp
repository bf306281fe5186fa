#include "railvib/soil/soil_params.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace railvib::soil {

namespace {

Material readMaterial(const ConfigNode& n) {
  Material m;
  m.young_modulus_pa = n.number("young_modulus_pa", Range::open(0.0, 1e13));
  m.density_kg_m3 = n.number("density_kg_m3", Range::open(0.0, 1e5));
  // nu >= 0.5 is incompressible (no finite P-wave speed); explicit FE needs nu < 0.5.
  m.poisson_ratio = n.number("poisson_ratio", Range{-1.0, 0.5, true, true});
  return m;
}

}  // namespace

std::vector<double> SoilParams::sleeperPositions() const {
  std::vector<double> x;
  const double L = sleeper_spacing_m;
  const long k_first = static_cast<long>(std::ceil((track_x_min_m - sleeper_offset_m) / L - 1e-9));
  const long k_last = static_cast<long>(std::floor((track_x_max_m - sleeper_offset_m) / L + 1e-9));
  for (long k = k_first; k <= k_last; ++k) x.push_back(sleeper_offset_m + static_cast<double>(k) * L);
  return x;
}

SoilParams loadSoilParams(const ConfigNode& root) {
  SoilParams p;
  const ConfigNode soil = root.section("soil");
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
  const ConfigNode mesh = soil.section("mesh");
  p.mesh.f_max_hz = mesh.number("f_max_hz", Range::open(0.0, 1e4), 60.0);
  p.mesh.elements_per_wavelength = mesh.number("elements_per_wavelength", Range::closed(4.0, 100.0), 8.0);
  p.mesh.x_min_m = mesh.number("x_min_m", Range::open(-1e5, 1e5));
  p.mesh.x_max_m = mesh.number("x_max_m", Range::open(-1e5, 1e5));
  p.mesh.y_min_m = mesh.number("y_min_m", Range::open(-1e5, 1e5));
  p.mesh.y_max_m = mesh.number("y_max_m", Range::open(-1e5, 1e5));
  p.mesh.depth_m = mesh.number("depth_m", Range::open(0.0, 1e5));
  if (!(p.mesh.x_max_m > p.mesh.x_min_m)) mesh.fail("x_max_m", "must be greater than x_min_m");
  if (!(p.mesh.y_max_m > p.mesh.y_min_m)) mesh.fail("y_max_m", "must be greater than y_min_m");
  p.mesh.max_plane_size_m = mesh.number("max_plane_size_m", Range::nonNegative(), 0.0);
  p.solver.safety_factor = mesh.number("safety_factor", Range{0.0, 1.0, true, false}, 0.9);
  p.solver.precision =
      mesh.choice("precision", {"float", "double"}, "float") == "float" ? Precision::Float : Precision::Double;
  p.solver.threads = static_cast<int>(mesh.integer("threads", 0, 256, 0));
  p.solver.kernel = kernelFromName(mesh.choice("kernel", {"element"}, "element"));
  p.max_memory_gb = mesh.number("max_memory_gb", Range::open(0.0, 1e4), 12.0);

  const ConfigNode b = soil.section("boundary");
  p.solver.boundary = loadBoundarySpec(b);
  const std::unique_ptr<SoilBoundary> boundary = makeSoilBoundary(p.solver.boundary);
  // The zone where the boundary alters the physics (e.g. a layer): receivers and loads stay out of it.
  const double layer = boundary->zoneThicknessM();
  const bool layer_bottom = boundary->zoneAlongBottom();
  const std::string layer_key = boundaryMethodName(p.solver.boundary.method);
  if (layer > 0.0 && (2.0 * layer >= p.mesh.x_max_m - p.mesh.x_min_m ||
                      2.0 * layer >= p.mesh.y_max_m - p.mesh.y_min_m || (layer_bottom && layer >= p.mesh.depth_m))) {
    b.section(layer_key).fail("thickness_m", "the absorbing zone would fill the soil box");
  }

  const ConfigNode out = soil.section("output");
  p.receiver_rate_hz = out.number("receiver_rate_hz", Range::open(0.0, 1e6), 1000.0);
  p.snapshot_rate_hz = out.number("snapshot_rate_hz", Range::open(0.0, 1e6), 100.0);
  const double ratio = p.receiver_rate_hz / p.snapshot_rate_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9 || ratio < 1.0) {
    out.fail("snapshot_rate_hz", "must divide receiver_rate_hz into an integer ratio >= 1");
  }
  p.solver.align_rate_hz = p.receiver_rate_hz;
  p.loads_outside_mesh = soil.section("loads").choice("outside_mesh", {"error", "drop"}, "error");
  p.start_from_static = soil.section("loads").flag("start_from_static", true);

  // Track: sleeper footprint and positions, load rate.
  const ConfigNode track = root.section("track");
  const ConfigNode sl = track.section("sleeper");
  p.sleeper_spacing_m = sl.number("spacing_m", Range::open(0.0, 100.0));
  p.sleeper_length_m = sl.number("length_m", Range::open(0.0, 100.0));
  p.sleeper_width_m = sl.number("width_m", Range::open(0.0, 100.0));
  p.sleeper_offset_m = sl.number("offset_m", Range::any(), 0.0);
  p.track_x_min_m = track.section("extent").number("x_min_m", Range::open(-1e5, 1e5));
  p.track_x_max_m = track.section("extent").number("x_max_m", Range::open(-1e5, 1e5));
  p.load_sample_rate_hz = track.section("output").number("load_sample_rate_hz", Range::open(0.0, 1e7), 2000.0);
  p.duration_s = root.section("simulation").number("duration_s", Range::open(0.0, 1e5));

  // Receivers: ground sensors, a line perpendicular to the track, building footprint points.
  const ConfigNode site = root.section("site");
  std::vector<std::string> origin;
  for (const ConfigNode& s : site.sectionList("ground_sensors")) {
    p.receivers.push_back({s.text("name"), s.number("x_m", Range::any()), s.number("y_m", Range::any()), 0.0});
    origin.push_back(s.keyPath());
  }
  if (out.has("receiver_line")) {
    const ConfigNode line = out.section("receiver_line");
    const double x = line.number("x_m", Range::any());
    const double y0 = line.number("y_min_m", Range::any());
    const double y1 = line.number("y_max_m", Range::any());
    const double step = line.number("step_m", Range::open(0.0, 1e4));
    if (y1 < y0) line.fail("y_max_m", "must be >= y_min_m");
    const long n = static_cast<long>(std::floor((y1 - y0) / step + 1e-9));
    for (long i = 0; i <= n; ++i) {
      const double y = y0 + step * static_cast<double>(i);
      std::ostringstream name;
      name << "line_y" << y;
      p.receivers.push_back({name.str(), x, y, 0.0});
      origin.push_back(line.keyPath());
    }
  }
  if (out.flag("building_receivers", true) && root.has("building")) {
    const ConfigNode bsite = site.section("building");
    const double gauge = site.number("rail_gauge_m", Range::open(0.0, 10.0));
    const double front = 0.5 * gauge + bsite.number("front_wall_distance_from_rail_m", Range::nonNegative());
    const double cx = bsite.number("center_x_m", Range::any());
    const ConfigNode bld = root.section("building");
    const double len = bld.number("length_m", Range::open(0.0, 1e3));
    const double wid = bld.number("width_m", Range::open(0.0, 1e3));
    // Corners, wall mid-points, centre, and the paper's response point (3/4 along, mid-width).
    const char* names[] = {"bldg_front_left", "bldg_front_mid", "bldg_front_right", "bldg_mid_left",  "bldg_centre",
                           "bldg_mid_right",  "bldg_back_left", "bldg_back_mid",    "bldg_back_right"};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        p.receivers.push_back({names[r * 3 + c], cx - 0.5 * len + 0.5 * len * c, front + 0.5 * wid * r, 0.0});
        origin.push_back(bsite.keyPath());
      }
    }
    p.receivers.push_back({"bldg_response_point", cx - 0.5 * len + 0.75 * len, front + 0.5 * wid, 0.0});
    origin.push_back(bsite.keyPath());
  }
  for (size_t i = 0; i < p.receivers.size(); ++i) {
    const ReceiverSpec& r = p.receivers[i];
    const bool inside = r.x_m >= p.mesh.x_min_m && r.x_m <= p.mesh.x_max_m && r.y_m >= p.mesh.y_min_m &&
                        r.y_m <= p.mesh.y_max_m && r.z_m <= 0.0 && -r.z_m <= p.mesh.depth_m;
    if (!inside) {
      std::ostringstream why;
      why << "receiver '" << r.name << "' (from " << origin[i] << ") at (" << r.x_m << ", " << r.y_m << ", " << r.z_m
          << ") m is outside the soil mesh box x [" << p.mesh.x_min_m << ", " << p.mesh.x_max_m << "], y ["
          << p.mesh.y_min_m << ", " << p.mesh.y_max_m << "], depth [0, " << p.mesh.depth_m << "] m";
      mesh.fail("x_min_m", why.str());
    }
    // Receivers inside the absorbing layer would record damped (wrong) motion.
    const double dist = std::min({r.x_m - p.mesh.x_min_m, p.mesh.x_max_m - r.x_m, r.y_m - p.mesh.y_min_m,
                                  p.mesh.y_max_m - r.y_m, layer_bottom ? p.mesh.depth_m + r.z_m : 1e300});
    if (layer > 0.0 && dist < layer) {
      std::ostringstream why;
      why << "receiver '" << r.name << "' (from " << origin[i] << ") at (" << r.x_m << ", " << r.y_m << ", " << r.z_m
          << ") m is " << dist << " m from the box face, inside the " << layer
          << " m absorbing zone of the boundary: enlarge soil.mesh or thin the zone";
      b.section(layer_key).fail("thickness_m", why.str());
    }
  }

  // Memory check before anything is allocated.
  StructuredMesh m;
  try {
    m = buildMesh(p.profile, p.mesh);
  } catch (const std::invalid_argument& e) {
    mesh.fail("f_max_hz", e.what());
  }
  // The boundary on this mesh (e.g. a PML must be at least one element thick).
  try {
    boundary->kernelElements(BoundaryContext{&m, nullptr, p.solver.absorbing});
  } catch (const std::invalid_argument& e) {
    b.section(layer_key).fail("thickness_m", e.what());
  }
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
  return p;
}

}  // namespace railvib::soil
