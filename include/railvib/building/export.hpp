// railvib/building: exports of the model for ParaView and for CalculiX/Abaqus.
#pragma once

#include <string>
#include <vector>

#include "railvib/building/modal.hpp"
#include "railvib/building/model.hpp"

namespace railvib::building {

/// The frame of the exported points: point in `frame_name` = point in frame `building` + offset_m
/// (for frame `track`: the origin of frame `building` in frame `track`, site.hpp BuildingPlacement).
struct ExportFrame {
  std::string frame_name = "building";
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
};

/// Legacy VTK unstructured grid (quads) with the group and section per cell and,
/// per mode, the translational mode shape as a point vector "mode_NN_<f>Hz". Points in `frame`
/// (the site's `track` frame puts the house beside the soil exports in ParaView).
void writeVtk(const BuildingModel& model, const std::vector<Mode>& modes, const std::string& path,
              const ExportFrame& frame = {});

/// Abaqus/CalculiX input: nodes, S4 elements, materials, *SHELL SECTION per section,
/// the foundation nodes fixed (*BOUNDARY) and a *FREQUENCY step for `mode_count` modes.
void writeInp(const BuildingModel& model, int mode_count, const std::string& path);

/// Frequencies (Hz) read back from a CalculiX .dat file (the EIGENVALUE OUTPUT table).
std::vector<double> readCalculixFrequencies(const std::string& dat_path);

}  // namespace railvib::building
