// railvib/soil: the choice of the soil boundary (soil.boundary.method) and its parameters.
#include "railvib/soil/boundary.hpp"

#include <stdexcept>

namespace railvib::soil {

// Each method lives in its own file.
std::unique_ptr<SoilBoundary> makeLysmerDashpots();
std::unique_ptr<SoilBoundary> makeGradedLayer(const GradedLayerSpec& spec);

std::string boundaryMethodName(BoundaryMethod method) {
  switch (method) {
    case BoundaryMethod::Dashpots:
      return "dashpots";
    case BoundaryMethod::GradedLayer:
      return "graded_layer";
    case BoundaryMethod::Pml:
      return "pml";
  }
  return "?";
}

std::unique_ptr<SoilBoundary> makeSoilBoundary(const BoundarySpec& spec) {
  switch (spec.method) {
    case BoundaryMethod::Dashpots:
      return makeLysmerDashpots();
    case BoundaryMethod::GradedLayer:
      return makeGradedLayer(spec.graded_layer);
    case BoundaryMethod::Pml:
      break;
  }
  throw std::invalid_argument("soil boundary '" + boundaryMethodName(spec.method) + "' is not available");
}

BoundarySpec loadBoundarySpec(const ConfigNode& b) {
  BoundarySpec spec;
  const std::string method = b.choice("method", {"dashpots", "graded_layer"});
  if (method == "dashpots") {
    spec.method = BoundaryMethod::Dashpots;
  } else if (method == "graded_layer") {
    spec.method = BoundaryMethod::GradedLayer;
    const ConfigNode g = b.section("graded_layer");
    spec.graded_layer.thickness_m = g.number("thickness_m", Range::positive());
    spec.graded_layer.max_alpha_1_s = g.number("max_alpha_1_s", Range::positive());
    spec.graded_layer.exponent = g.number("exponent", Range::closed(0.25, 8.0), 2.0);
    spec.graded_layer.bottom = g.flag("bottom", true);
  }
  return spec;
}

}  // namespace railvib::soil
