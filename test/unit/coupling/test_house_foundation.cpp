// The house as a rigid body in the soil (coupling/house_foundation.hpp): the frame change from the
// building's DOFs to the soil's, the masses, and the refusal of impossible placements.
#include <gtest/gtest.h>

#include "railvib/building/model.hpp"
#include "railvib/common/config.hpp"
#include "railvib/coupling/house_foundation.hpp"
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
  const Config cfg = harenConfig();
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
  EXPECT_EQ(refusal({}), "accepted");
}
