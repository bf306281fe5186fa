// railvib/soil: a small soil box cut by voids and inclusions, run by railvib's explicit solver and
// written for CalculiX (Dhondt, The Finite Element Method for Three-Dimensional Thermomechanical
// Applications, Wiley 2004; `ccx`, Debian package calculix-ccx) as an independent peer: the same
// trilinear hexahedra (C3D8, 2 x 2 x 2 Gauss points), lumped mass and central-difference explicit
// integration, so the two codes must agree to the scheme's time-discretisation difference. What the
// comparison checks is the seam of the inclusions: CalculiX meshes the cut-out by leaving its
// elements out, railvib by taking their stiffness and mass back (MeshSpec::inclusions).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"

namespace railvib::soil {

struct PeerCase {
  /// The box (inclusions included); its bottom is fixed, its other faces are free.
  StructuredMesh mesh;
  /// Vertical point load (down) at surface node (i, j) with a Hann pulse of this duration and peak.
  size_t load_i = 0, load_j = 0;
  double pulse_s = 0.01, peak_force_n = 1.0e3;
  /// Sample points of the piecewise-linear load amplitude (both codes use the same polyline).
  size_t amplitude_points = 41;
  double dt_s = 2.0e-5, duration_s = 0.05;
  /// Displacements are compared every `output_every` steps at these nodes (mesh node indices).
  size_t output_every = 10;
  std::vector<size_t> output_nodes;
};

/// The default case: 12 x 10 x 8 elements of 0.25 m, Haren layer 1 over layer 2, an open pit beside
/// the load (x [-0.5, 0.25], y [-0.5, 0.5], 1 m deep) and a concrete block under the far surface.
PeerCase voidPeerCase();

/// Displacement histories: [output time][output node][component x, y, d].
struct PeerHistory {
  std::vector<double> time_s;
  std::vector<double> u_m;  // time-major, 3 per node
};

/// The CalculiX input deck of the case: nodes of the solid elements (numbered node index + 1, z up),
/// one C3D8 element set per material, fixed bottom, the load on a tabular amplitude, and
/// *DYNAMIC, EXPLICIT with a fixed increment; *NODE PRINT of the output nodes.
std::string calculixInput(const PeerCase& c);

/// Parse the displacements of a CalculiX .dat file (*NODE PRINT, U) into the case's node order and
/// frame (x, y, d down). Throws std::runtime_error on a malformed or incomplete file.
PeerHistory readCalculixDisplacements(const std::string& dat_text, const PeerCase& c);

/// railvib's run of the case (double precision, no damping), sampled as CalculiX prints.
PeerHistory runPeerCase(const PeerCase& c);

/// The largest over the nodes of max |a - b| / max |b| over the node's times and components (infinite
/// when the sizes differ).
double peerDifference(const PeerHistory& a, const PeerHistory& b);

}  // namespace railvib::soil
