// railvib/soil: Lysmer-Kuhlemeyer viscous boundary (BoundaryMethod::Dashpots).
//
// On every absorbing face, each face element's area is shared by its 4 nodes;
// a node gets c_n = rho Vp A / 4 normal to the face and c_t = rho Vs A / 4 in
// the two tangential directions (Lysmer & Kuhlemeyer 1969), with the material
// of the element level the face belongs to (the bottom face: the deepest level).
#include "railvib/soil/boundary.hpp"

namespace railvib::soil {

void addLysmerDashpots(const StructuredMesh& m, const AbsorbingFaces& faces, std::vector<double> c[3]) {
  auto face = [&](size_t n0, size_t n1, size_t n2, size_t n3, double area, const Material& mat, int normal) {
    const double cn = mat.density_kg_m3 * mat.vp() * area / 4.0;
    const double ct = mat.density_kg_m3 * mat.vs() * area / 4.0;
    for (size_t nd : {n0, n1, n2, n3}) {
      for (int d = 0; d < 3; ++d) c[d][nd] += (d == normal) ? cn : ct;
    }
  };
  for (size_t k = 0; k < m.nz; ++k) {
    const double hz = m.z[k + 1] - m.z[k];
    const Material& mat = m.levelMaterial(k);
    for (size_t j = 0; j < m.ny; ++j) {
      if (faces.x_min)
        face(m.node(0, j, k), m.node(0, j + 1, k), m.node(0, j, k + 1), m.node(0, j + 1, k + 1), m.hy * hz, mat, 0);
      if (faces.x_max)
        face(m.node(m.nx, j, k), m.node(m.nx, j + 1, k), m.node(m.nx, j, k + 1), m.node(m.nx, j + 1, k + 1), m.hy * hz,
             mat, 0);
    }
    for (size_t i = 0; i < m.nx; ++i) {
      if (faces.y_min)
        face(m.node(i, 0, k), m.node(i + 1, 0, k), m.node(i, 0, k + 1), m.node(i + 1, 0, k + 1), m.hx * hz, mat, 1);
      if (faces.y_max)
        face(m.node(i, m.ny, k), m.node(i + 1, m.ny, k), m.node(i, m.ny, k + 1), m.node(i + 1, m.ny, k + 1), m.hx * hz,
             mat, 1);
    }
  }
  if (faces.bottom) {
    const size_t k = m.nz;
    const Material& mat = m.levelMaterial(m.nz - 1);
    for (size_t j = 0; j < m.ny; ++j) {
      for (size_t i = 0; i < m.nx; ++i)
        face(m.node(i, j, k), m.node(i + 1, j, k), m.node(i, j + 1, k), m.node(i + 1, j + 1, k), m.hx * m.hy, mat, 2);
    }
  }
}

namespace {

class LysmerDashpots final : public SoilBoundary {
 public:
  BoundaryMethod method() const override { return BoundaryMethod::Dashpots; }
  void addNodalDamping(const BoundaryContext& ctx, std::vector<double> c[3]) const override {
    addLysmerDashpots(*ctx.mesh, ctx.faces, c);
  }
  nlohmann::json summary() const override { return {{"method", "dashpots"}}; }
};

}  // namespace

std::unique_ptr<SoilBoundary> makeLysmerDashpots() { return std::make_unique<LysmerDashpots>(); }

}  // namespace railvib::soil
