// railvib/soil: the choice of the soil boundary (soil.boundary.method) and its parameters.
#include "railvib/soil/boundary.hpp"

#include <stdexcept>

namespace railvib::soil {

// Each method lives in its own file.
std::unique_ptr<SoilBoundary> makeLysmerDashpots();
std::unique_ptr<SoilBoundary> makeGradedLayer(const GradedLayerSpec& spec);
std::unique_ptr<SoilBoundary> makePml(const PmlSpec& spec);

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
      return makePml(spec.pml);
  }
  throw std::invalid_argument("soil boundary '" + boundaryMethodName(spec.method) + "' is not available");
}

BoundarySpec loadBoundarySpec(const ConfigNode& b) {
  BoundarySpec spec;
  const std::string method = b.choice("method", {"dashpots", "graded_layer", "pml"});
  // The section of every method present is validated (a config may keep the settings of a method it
  // does not use, e.g. to switch back by one override); the chosen method's section is required.
  if (method == "graded_layer" || b.has("graded_layer")) {
    const ConfigNode g = b.section("graded_layer");
    spec.graded_layer.thickness_m = g.number("thickness_m", Range::positive());
    spec.graded_layer.max_alpha_1_s = g.number("max_alpha_1_s", Range::positive());
    spec.graded_layer.exponent = g.number("exponent", Range::closed(0.25, 8.0), 2.0);
    spec.graded_layer.bottom = g.flag("bottom", true);
  }
  if (method == "pml" || b.has("pml")) {
    const ConfigNode g = b.section("pml");
    const PmlSpec d;  // defaults
    spec.pml.thickness_m = g.number("thickness_m", Range::positive());
    // R = 1 would be no damping, R -> 0 an infinitely steep profile.
    spec.pml.reflection_coefficient =
        g.number("reflection_coefficient", Range::open(0.0, 1.0), d.reflection_coefficient);
    spec.pml.exponent = g.number("exponent", Range::closed(0.5, 6.0), d.exponent);
    spec.pml.max_kappa = g.number("max_kappa", Range::closed(1.0, 50.0), d.max_kappa);
    spec.pml.alpha_1_s = g.number("alpha_1_s", Range::closed(0.0, 1e4), d.alpha_1_s);
    spec.pml.perpendicular_ratio = g.number("perpendicular_ratio", Range::closed(0.0, 1.0), d.perpendicular_ratio);
    spec.pml.bottom = g.flag("bottom", d.bottom);
    spec.pml.outer_dashpots = g.flag("outer_dashpots", d.outer_dashpots);
  }
  for (BoundaryMethod m : {BoundaryMethod::Dashpots, BoundaryMethod::GradedLayer, BoundaryMethod::Pml}) {
    if (boundaryMethodName(m) == method) spec.method = m;
  }
  return spec;
}

}  // namespace railvib::soil
