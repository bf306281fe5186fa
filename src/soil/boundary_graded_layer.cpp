// railvib/soil: graded mass-proportional absorbing layer (BoundaryMethod::GradedLayer).
//
// Along the absorbing faces (and the bottom, unless switched off) a layer of
// thickness L gets the diagonal damping alpha(s) M, alpha = alpha_max (s / L)^n,
// s in [0, 1] the relative depth into the layer (the largest over the faces
// a node is near), in front of the Lysmer-Kuhlemeyer dashpots at the outer
// faces. Diagonal, so it is treated semi-implicitly and does not limit the step.
// Measured reflections: docs/soil.md, "Boundary reflections".
#include <algorithm>
#include <cmath>

#include "railvib/soil/boundary.hpp"

namespace railvib::soil {

namespace {

class GradedLayer final : public SoilBoundary {
 public:
  explicit GradedLayer(const GradedLayerSpec& spec) : spec_(spec) {}

  BoundaryMethod method() const override { return BoundaryMethod::GradedLayer; }
  double zoneThicknessM() const override { return active() ? spec_.thickness_m : 0.0; }
  bool zoneAlongBottom() const override { return spec_.bottom; }

  void addNodalDamping(const BoundaryContext& ctx, std::vector<double> c[3]) const override {
    const StructuredMesh& m = *ctx.mesh;
    addLysmerDashpots(m, ctx.faces, c);
    if (!active()) return;
    const double L = spec_.thickness_m;
    for (size_t k = 0; k <= m.nz; ++k) {
      for (size_t j = 0; j <= m.ny; ++j) {
        for (size_t i = 0; i <= m.nx; ++i) {
          double s = 0.0;
          auto pen = [&](bool on, double dist) {
            if (on && dist < L) s = std::max(s, (L - dist) / L);
          };
          pen(ctx.faces.x_min, m.x(i) - m.x0);
          pen(ctx.faces.x_max, m.xMax() - m.x(i));
          pen(ctx.faces.y_min, m.y(j) - m.y0);
          pen(ctx.faces.y_max, m.yMax() - m.y(j));
          pen(ctx.faces.bottom && spec_.bottom, m.depth() - m.z[k]);
          if (s > 0.0) {
            const size_t nd = m.node(i, j, k);
            const double add = spec_.max_alpha_1_s * std::pow(s, spec_.exponent) * (*ctx.mass)[nd];
            for (int d = 0; d < 3; ++d) c[d][nd] += add;
          }
        }
      }
    }
  }

  nlohmann::json summary() const override {
    return {{"method", "graded_layer"},
            {"thickness_m", zoneThicknessM()},
            {"max_alpha_1_s", spec_.max_alpha_1_s},
            {"exponent", spec_.exponent},
            {"bottom", spec_.bottom}};
  }

 private:
  bool active() const { return spec_.thickness_m > 0.0 && spec_.max_alpha_1_s > 0.0; }
  GradedLayerSpec spec_;
};

}  // namespace

std::unique_ptr<SoilBoundary> makeGradedLayer(const GradedLayerSpec& spec) {
  return std::make_unique<GradedLayer>(spec);
}

}  // namespace railvib::soil
