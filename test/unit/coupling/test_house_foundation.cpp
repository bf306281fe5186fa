// The house as a rigid body in the soil (coupling/house_foundation.hpp): the frame change from the
// building's DOFs to the soil's, the masses, and the refusal of impossible placements.
#include <gtest/gtest.h>

#include <map>

#include "railvib/building/model.hpp"
#include "railvib/common/config.hpp"
#include "railvib/coupling/house_foundation.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/soil_params.hpp"

using namespace railvib;

namespace {

Config harenConfig(std::vector<std::string> overrides = {}) {
  overrides.push_back("building.mesh.element_size_m=1.0");  // fast, same physics
  overrides.push_back("building.coupling=two_way");
  return Config::load(std::string(RAILVIB_SOURCE_DIR) + "/config/haren.yaml", overrides);
}

coupling::HouseFoundation foundationOf(const Config& cfg) {
  const building::BuildingModel model(building::loadBuildingParams(cfg.root()));
  return coupling::houseFoundation(cfg.root(), model, soil::loadSoilParams(cfg.root()));
}

std::string refusal(const std::vector<std::string>& overrides) {
  try {
    foundationOf(harenConfig(overrides));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

// The superstructure's rigid mass matrix in the soil's DOFs (x, y, d down) equals the one computed
// directly from the house's nodal masses with the soil's rigid map u + w x r, r = (x, y, -z).
TEST(HouseFoundation, SoilFrameMassesAreTheHousesMasses) {
  const Config cfg = harenConfig({"building.foundation.model=rigid"});  // the box's concrete as added mass
  const building::BuildingModel model(building::loadBuildingParams(cfg.root()));
  const coupling::HouseFoundation h = coupling::houseFoundation(cfg.root(), model, soil::loadSoilParams(cfg.root()));
  const building::BuildingParams& bp = model.params();
  Eigen::Matrix<double, 6, 6> direct = Eigen::Matrix<double, 6, 6>::Zero();
  for (int d : model.freeDofs()) {
    if (d % building::kDofPerNode >= 3) continue;  // lumped mass: translations only
    const Eigen::Vector3d& xb = model.mesh().nodes[d / building::kDofPerNode];
    const Eigen::Vector3d r(xb.x() - 0.5 * bp.length_m, xb.y() - 0.5 * bp.width_m, -xb.z());
    Eigen::Matrix<double, 3, 6> ra;
    ra.leftCols<3>().setIdentity();
    ra.rightCols<3>() << 0.0, r.z(), -r.y(), -r.z(), 0.0, r.x(), r.y(), -r.x(), 0.0;
    const int c = d % building::kDofPerNode;
    // The building's vertical axis points up, the soil's down: the component c of the soil map.
    const double sign = c == 2 ? -1.0 : 1.0;
    const Eigen::Matrix<double, 1, 6> row = sign * ra.row(c);
    direct += model.mass()[d] * row.transpose() * row;
  }
  EXPECT_LT((direct - h.body.structure.rigid_mass).norm(), 1e-9 * direct.norm());
  // The house stands above the ground (d < 0): sway couples to rocking with u_x w_y < 0.
  EXPECT_LT(h.body.structure.rigid_mass(0, 4), 0.0);
  // The box: concrete in excess of the soil it displaces (layer 1 at 1876 kg/m^3, concrete 2400).
  EXPECT_NEAR(h.displaced_soil_mass_kg, 1876.0 / 2400.0 * h.concrete_mass_kg, 1e-6 * h.concrete_mass_kg);
  EXPECT_NEAR(h.body.added_mass(2, 2), h.concrete_mass_kg - h.displaced_soil_mass_kg, 1e-6 * h.concrete_mass_kg);
  // Modes kept up to twice the soil's f_max (2 x 50 Hz).
  EXPECT_NEAR(h.reduction.fmax_hz, 100.0, 1e-12);
  EXPECT_LT(h.reduction.circular_frequency_rad_s.maxCoeff(), 2.0 * M_PI * 100.0);
}

TEST(HouseFoundation, ImpossiblePlacementsAreRefusedWithTheKey) {
  const std::string outside = refusal({"site.building.center_x_m=30.0"});
  EXPECT_NE(outside.find("site.building.center_x_m"), std::string::npos) << outside;
  EXPECT_NE(outside.find("not inside the soil box"), std::string::npos) << outside;
  const std::string deep = refusal({"building.foundation.depth_m=20.0"});
  EXPECT_NE(deep.find("building.foundation.depth_m"), std::string::npos) << deep;
  const std::string on_track = refusal({"site.building.front_wall_distance_from_rail_m=0.3"});
  EXPECT_NE(on_track.find("overlaps the track"), std::string::npos) << on_track;
  const std::string few_modes = refusal({"building.coupling_modes_max_hz=60.0"});
  EXPECT_NE(few_modes.find("building.coupling_modes_max_hz"), std::string::npos) << few_modes;
  const std::string model = refusal({"building.foundation.model=slab"});
  EXPECT_NE(model.find("building.foundation.model"), std::string::npos) << model;
  EXPECT_EQ(refusal({}), "accepted");
}

// building.foundation.model meshed: the box as a closed concrete shell on the soil's node planes (base
// slab, ground slab, four walls, disjoint, the cavity between them the only gap), the house on a ring.
TEST(HouseFoundation, MeshedFoundationIsAClosedConcreteShell) {
  const Config cfg = harenConfig({"building.foundation.model=meshed"});
  soil::SoilParams sp = soil::loadSoilParams(cfg.root());
  const building::BuildingModel model(building::loadBuildingParams(cfg.root()));
  const building::BuildingParams& bp = model.params();
  const coupling::HouseFoundation h = coupling::houseFoundation(cfg.root(), model, sp);
  ASSERT_EQ(h.inclusions.size(), 6u);  // the ground slab rests on the fill at Haren
  std::map<std::string, const soil::InclusionSpec*> part;
  double volume = 0.0;
  for (const soil::InclusionSpec& s : h.inclusions) {
    EXPECT_TRUE(s.implicit) << s.name;
    EXPECT_EQ(s.rayleigh_beta_s, building::rayleighCoefficients(bp).beta_s) << s.name;
    EXPECT_EQ(s.material.young_modulus_pa, bp.foundation.young_modulus_pa) << s.name;
    part[s.name.substr(std::string("house_foundation_").size())] = &s;
    volume += (s.x_max_m - s.x_min_m) * (s.y_max_m - s.y_min_m) * (s.bottom_m - s.top_m);
  }
  for (size_t a = 0; a < h.inclusions.size(); ++a) {
    for (size_t b = a + 1; b < h.inclusions.size(); ++b) {
      const soil::InclusionSpec &p = h.inclusions[a], &q = h.inclusions[b];
      const double ox = std::min(p.x_max_m, q.x_max_m) - std::max(p.x_min_m, q.x_min_m);
      const double oy = std::min(p.y_max_m, q.y_max_m) - std::max(p.y_min_m, q.y_min_m);
      const double oz = std::min(p.bottom_m, q.bottom_m) - std::max(p.top_m, q.top_m);
      EXPECT_FALSE(ox > 1e-9 && oy > 1e-9 && oz > 1e-9) << p.name << " overlaps " << q.name;
    }
  }
  const soil::InclusionSpec &base = *part.at("base_slab"), &ground = *part.at("ground_slab");
  // The outer box within half an element of the house's footprint and the foundation's depth.
  const soil::StructuredMesh mesh = soil::buildMesh(sp.profile, sp.mesh);
  size_t k = 0;
  while (mesh.z[k + 1] < bp.foundation_depth_m) ++k;
  EXPECT_NEAR(base.x_min_m, bp.placement.origin_x_m, 0.5 * mesh.hx);
  EXPECT_NEAR(base.x_max_m, bp.placement.origin_x_m + bp.length_m, 0.5 * mesh.hx);
  EXPECT_NEAR(base.y_min_m, bp.placement.origin_y_m, 0.5 * mesh.hy);
  EXPECT_NEAR(base.y_max_m, bp.placement.origin_y_m + bp.width_m, 0.5 * mesh.hy);
  EXPECT_NEAR(base.bottom_m, bp.foundation_depth_m, 0.5 * (mesh.z[k + 1] - mesh.z[k]));
  EXPECT_EQ(ground.top_m, 0.0);
  // Each slab as thick as the house's within half an element (at least one element).
  EXPECT_NEAR(ground.bottom_m - ground.top_m, bp.floor_thickness_m, 0.5 * mesh.z[1]);
  EXPECT_NEAR(base.bottom_m - base.top_m, bp.base_slab_thickness_m, 0.5 * (mesh.z[k + 1] - mesh.z[k]));
  // Closed: the walls' volume and the slabs' fill the outer box but for the cavity between them.
  const double cavity = (part.at("right_wall")->x_min_m - part.at("left_wall")->x_max_m) *
                        (part.at("back_wall")->y_min_m - part.at("front_wall")->y_max_m) *
                        (base.top_m - ground.bottom_m);
  const double outer = (base.x_max_m - base.x_min_m) * (base.y_max_m - base.y_min_m) * base.bottom_m;
  EXPECT_GT(cavity, 0.0);
  EXPECT_NEAR(volume, outer - cavity, 1e-9 * outer);
  // The rigid body is the ring on the walls' tops: no added concrete, no depth.
  EXPECT_EQ(h.body.depth_m, 0.0);
  EXPECT_EQ(h.body.ring_width_m, bp.foundation_wall_thickness_m);
  EXPECT_EQ(h.body.added_mass.norm(), 0.0);
  EXPECT_GT(h.body.structure.rigid_mass(2, 2), 0.0);

  // attachHouse puts the shell into the soil's inclusions once; a second house of the same name is refused.
  const size_t before = sp.mesh.inclusions.size();
  ASSERT_EQ(coupling::attachHouse(cfg.root(), sp).size(), 1u);
  EXPECT_EQ(sp.mesh.inclusions.size(), before + 6);
  try {
    coupling::attachHouse(cfg.root(), sp);
    ADD_FAILURE() << "a clash of inclusion names was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("soil.inclusions"), std::string::npos) << e.what();
  }
  // Slabs that leave no cavity between them on the mesh are refused at the model key.
  const std::string coarse =
      refusal({"building.foundation.model=meshed", "building.foundation.base_slab_thickness_m=0.7"});
  EXPECT_NE(coarse.find("building.foundation.model"), std::string::npos) << coarse;
}

// soil.mesh.extent mode auto: the box holds every soil receiver (the sensors, the receiver line, the
// house's points), the section plane and the sleepers across the track, with the margins and the
// boundary's absorbing zone beyond them, exactly; a sensor moved out moves the box with it.
TEST(SoilBox, AnAutomaticBoxHoldsTheSiteWithItsMarginsAndFollowsASensor) {
  const auto box = [](const Config& cfg) {
    return soil::loadSoilParams(cfg.root(), coupling::houseReceivers(cfg.root(), true));
  };
  const Config cfg = harenConfig({"soil.mesh.extent.mode=auto"});
  const soil::SoilParams p = box(cfg);
  ASSERT_TRUE(p.box_fitted);
  // The perfectly matched layer outside the margins (soil.boundary.pml.thickness_m).
  const double zone =
      cfg.root().section("soil").section("boundary").section("pml").number("thickness_m", Range::positive());
  double x0 = 1e300, x1 = -1e300, y0 = -0.5 * p.track.length_m, y1 = 0.5 * p.track.length_m;
  for (const soil::ReceiverSpec& r : p.receivers) {
    x0 = std::min(x0, r.x_m), x1 = std::max(x1, r.x_m), y0 = std::min(y0, r.y_m), y1 = std::max(y1, r.y_m);
  }
  EXPECT_NEAR(p.mesh.x_min_m, x0 - 10.0 - zone, 1e-12);
  EXPECT_NEAR(p.mesh.x_max_m, x1 + 10.0 + zone, 1e-12);
  EXPECT_NEAR(p.mesh.y_min_m, y0 - 2.0 - zone, 1e-12);
  EXPECT_NEAR(p.mesh.y_max_m, y1 + 2.0 + zone, 1e-12);
  // Haren: the receiver line reaches y = 15 m, the house's footprint |x| < 5 m, the track y = -1.3 m.
  EXPECT_NEAR(p.mesh.y_max_m, 15.0 + 2.0 + zone, 1e-12);
  EXPECT_NEAR(p.mesh.y_min_m, -1.3 - 2.0 - zone, 1e-12);
  EXPECT_LE(x1, 5.0);  // the house's front wall spans x [-5, 5] m
  EXPECT_GT(x1, 4.0);
  // The 8 m sensor moved to 25 m (and 3 m along the track): the box follows; the fixed box refuses it.
  const std::string moved =
      "virtual_sensors.sensors=[{name: ground_2m, kind: free_field, x_m: 0.0, y_m: 2.0}, "
      "{name: ground_8m, kind: free_field, x_m: -8.0, y_m: 25.0}, "
      "{name: house_ground_floor, kind: foundation, point: ground_floor, x_m: 7.5, y_m: 3.5, z_m: 0.0}, "
      "{name: house_first_floor, kind: floor, point: first_floor, x_m: 7.5, y_m: 3.5, z_m: 2.5}]";
  const soil::SoilParams q = box(harenConfig({"soil.mesh.extent.mode=auto", moved}));
  EXPECT_NEAR(q.mesh.y_max_m, 25.0 + 2.0 + zone, 1e-12);
  EXPECT_NEAR(q.mesh.x_min_m, -8.0 - 10.0 - zone, 1e-12);
  EXPECT_NEAR(q.mesh.x_max_m, p.mesh.x_max_m, 1e-12);
  try {
    box(harenConfig({moved}));
    ADD_FAILURE() << "the fixed box took a sensor outside it";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("virtual_sensors.sensors[1]"), std::string::npos) << e.what();
  }
}
