#include "railvib/building/export.hpp"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "railvib/io/atomic_file.hpp"

namespace railvib::building {

void writeVtk(const BuildingModel& model, const std::vector<Mode>& modes, const std::string& path,
              const ExportFrame& frame) {
  const BuildingMesh& mesh = model.mesh();
  io::AtomicFile file(path);
  std::ostream& os = file.stream();
  os << std::setprecision(9);
  os << "# vtk DataFile Version 3.0\nrailvib building model and mode shapes (frame " << frame.frame_name
     << ", m)\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  os << "POINTS " << mesh.nodes.size() << " double\n";
  for (const auto& node : mesh.nodes) {
    const Eigen::Vector3d x = node + frame.offset_m;
    os << x.x() << " " << x.y() << " " << x.z() << "\n";
  }
  os << "CELLS " << mesh.elements.size() << " " << 5 * mesh.elements.size() << "\n";
  for (const auto& e : mesh.elements)
    os << "4 " << e.nodes[0] << " " << e.nodes[1] << " " << e.nodes[2] << " " << e.nodes[3] << "\n";
  os << "CELL_TYPES " << mesh.elements.size() << "\n";
  for (size_t i = 0; i < mesh.elements.size(); ++i) os << "9\n";
  os << "CELL_DATA " << mesh.elements.size() << "\nSCALARS group int 1\nLOOKUP_TABLE default\n";
  for (const auto& e : mesh.elements) os << e.group << "\n";
  os << "SCALARS thickness_m double 1\nLOOKUP_TABLE default\n";
  for (const auto& e : mesh.elements) os << mesh.sections[e.section].shell.thickness_m << "\n";
  os << "POINT_DATA " << mesh.nodes.size() << "\nSCALARS foundation int 1\nLOOKUP_TABLE default\n";
  for (size_t n = 0; n < mesh.nodes.size(); ++n) os << (model.foundationNode()[n] ? 1 : 0) << "\n";
  for (size_t m = 0; m < modes.size(); ++m) {
    // scale to a 0.5 m maximum displacement for viewing
    double amax = 0.0;
    for (size_t n = 0; n < mesh.nodes.size(); ++n)
      for (int d = 0; d < 3; ++d) amax = std::max(amax, std::abs(modes[m].shape[6 * n + d]));
    const double scale = amax > 0.0 ? 0.5 / amax : 1.0;
    char name[64];
    std::snprintf(name, sizeof(name), "mode_%02zu_%.2fHz", m + 1, modes[m].frequency_hz);
    os << "VECTORS " << name << " double\n";
    for (size_t n = 0; n < mesh.nodes.size(); ++n)
      os << scale * modes[m].shape[6 * n] << " " << scale * modes[m].shape[6 * n + 1] << " "
         << scale * modes[m].shape[6 * n + 2] << "\n";
  }
  file.commit();
}

void writeInp(const BuildingModel& model, int mode_count, const std::string& path) {
  const BuildingMesh& mesh = model.mesh();
  io::AtomicFile file(path);
  std::ostream& os = file.stream();
  os << std::setprecision(10);
  os << "*HEADING\nrailvib building model (fixed base), SI units, building frame\n";
  os << "*NODE, NSET=NALL\n";
  for (size_t n = 0; n < mesh.nodes.size(); ++n)
    os << n + 1 << ", " << mesh.nodes[n].x() << ", " << mesh.nodes[n].y() << ", " << mesh.nodes[n].z() << "\n";
  int id = 1;
  for (size_t s = 0; s < mesh.sections.size(); ++s) {
    bool any = false;
    for (const auto& e : mesh.elements) any = any || e.section == static_cast<int>(s);
    if (!any) continue;
    os << "*ELEMENT, TYPE=S4, ELSET=" << mesh.sections[s].name << "\n";
    for (const auto& e : mesh.elements) {
      if (e.section != static_cast<int>(s)) continue;
      os << id++ << ", " << e.nodes[0] + 1 << ", " << e.nodes[1] + 1 << ", " << e.nodes[2] + 1 << ", " << e.nodes[3] + 1
         << "\n";
    }
  }
  for (const auto& sec : mesh.sections) {
    os << "*MATERIAL, NAME=" << sec.name << "_mat\n*ELASTIC\n"
       << sec.shell.young_modulus_pa << ", " << sec.shell.poisson << "\n*DENSITY\n"
       << sec.shell.density_kg_m3 << "\n";
  }
  for (size_t s = 0; s < mesh.sections.size(); ++s) {
    bool any = false;
    for (const auto& e : mesh.elements) any = any || e.section == static_cast<int>(s);
    if (!any) continue;
    os << "*SHELL SECTION, ELSET=" << mesh.sections[s].name << ", MATERIAL=" << mesh.sections[s].name << "_mat\n"
       << mesh.sections[s].shell.thickness_m << "\n";
  }
  os << "*NSET, NSET=FOUNDATION\n";
  std::vector<size_t> fixed;
  for (size_t n = 0; n < mesh.nodes.size(); ++n)
    if (model.foundationNode()[n]) fixed.push_back(n + 1);
  for (size_t i = 0; i < fixed.size(); ++i)
    os << fixed[i] << (i + 1 == fixed.size() ? "" : (i % 16 == 15 ? ",\n" : ", "));
  os << "\n*BOUNDARY\nFOUNDATION, 1, 3\n";
  os << "*STEP\n*FREQUENCY\n" << mode_count << "\n*NODE FILE\nU\n*END STEP\n";
  file.commit();
}

std::vector<double> readCalculixFrequencies(const std::string& dat_path) {
  std::ifstream in(dat_path);
  if (!in) throw std::runtime_error("cannot read " + dat_path);
  std::vector<double> f;
  std::string line;
  bool table = false;
  while (std::getline(in, line)) {
    if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) {
      table = true;
      f.clear();
      continue;
    }
    if (!table) continue;
    if (line.find("P A R T I C I P A T I O N") != std::string::npos) break;
    std::istringstream ls(line);
    int mode;
    double eig, rad, cyc, imag;
    if (ls >> mode >> eig >> rad >> cyc >> imag) f.push_back(cyc);
  }
  return f;
}

}  // namespace railvib::building
