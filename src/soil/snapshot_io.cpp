#include "railvib/soil/snapshot_io.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "railvib/io/atomic_file.hpp"

namespace railvib::soil {

namespace {
template <class T>
void put(std::ostream& o, T v) {
  o.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <class T>
T get(std::istream& in, const std::string& path) {
  T v{};
  if (!in.read(reinterpret_cast<char*>(&v), sizeof(T))) throw std::runtime_error(path + ": truncated snapshot file");
  return v;
}
}  // namespace

void writeSnapshots(const std::string& path, const std::vector<SurfaceSnapshot>& snapshots) {
  io::AtomicFile file(path, std::ios::out | std::ios::binary);
  auto& o = file.stream();
  o.write("RVBSNAP1", 8);
  const SurfaceSnapshot ref = snapshots.empty() ? SurfaceSnapshot{} : snapshots.front();
  put<uint64_t>(o, ref.nx_nodes);
  put<uint64_t>(o, ref.ny_nodes);
  put<double>(o, ref.x0_m);
  put<double>(o, ref.y0_m);
  put<double>(o, ref.dx_m);
  put<double>(o, ref.dy_m);
  put<uint64_t>(o, snapshots.size());
  for (const auto& s : snapshots) {
    if (s.nx_nodes != ref.nx_nodes || s.ny_nodes != ref.ny_nodes || s.vz_up_m_s.size() != s.nx_nodes * s.ny_nodes) {
      throw std::runtime_error("writeSnapshots: snapshots on different grids");
    }
    put<uint64_t>(o, s.index);
    put<double>(o, s.time_s);
    o.write(reinterpret_cast<const char*>(s.vz_up_m_s.data()),
            static_cast<std::streamsize>(s.vz_up_m_s.size() * sizeof(float)));
  }
  file.commit();
}

std::vector<SurfaceSnapshot> readSnapshots(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  char magic[8];
  if (!in.read(magic, 8) || std::memcmp(magic, "RVBSNAP1", 8) != 0) {
    throw std::runtime_error(path + ": not a railvib snapshot file");
  }
  SurfaceSnapshot proto;
  proto.nx_nodes = get<uint64_t>(in, path);
  proto.ny_nodes = get<uint64_t>(in, path);
  proto.x0_m = get<double>(in, path);
  proto.y0_m = get<double>(in, path);
  proto.dx_m = get<double>(in, path);
  proto.dy_m = get<double>(in, path);
  const uint64_t count = get<uint64_t>(in, path);
  if (proto.nx_nodes * proto.ny_nodes > (uint64_t{1} << 34)) throw std::runtime_error(path + ": bad grid size");
  std::vector<SurfaceSnapshot> out;
  for (uint64_t c = 0; c < count; ++c) {
    SurfaceSnapshot s = proto;
    s.index = get<uint64_t>(in, path);
    s.time_s = get<double>(in, path);
    s.vz_up_m_s.resize(s.nx_nodes * s.ny_nodes);
    if (!in.read(reinterpret_cast<char*>(s.vz_up_m_s.data()),
                 static_cast<std::streamsize>(s.vz_up_m_s.size() * sizeof(float)))) {
      throw std::runtime_error(path + ": truncated snapshot file");
    }
    out.push_back(std::move(s));
  }
  return out;
}

void writeSectionSnapshots(const std::string& path, const std::vector<SectionSnapshot>& snapshots) {
  io::AtomicFile file(path, std::ios::out | std::ios::binary);
  auto& o = file.stream();
  o.write("RVBSECT1", 8);
  const SectionSnapshot ref = snapshots.empty() ? SectionSnapshot{} : snapshots.front();
  put<uint64_t>(o, ref.ny_nodes);
  put<uint64_t>(o, ref.depth_m.size());
  put<double>(o, ref.x_m);
  put<double>(o, ref.y0_m);
  put<double>(o, ref.dy_m);
  for (double d : ref.depth_m) put<double>(o, d);
  put<uint64_t>(o, snapshots.size());
  for (const auto& s : snapshots) {
    if (s.ny_nodes != ref.ny_nodes || s.depth_m != ref.depth_m || s.vz_up_m_s.size() != s.ny_nodes * s.depth_m.size()) {
      throw std::runtime_error("writeSectionSnapshots: snapshots on different grids");
    }
    put<uint64_t>(o, s.index);
    put<double>(o, s.time_s);
    o.write(reinterpret_cast<const char*>(s.vz_up_m_s.data()),
            static_cast<std::streamsize>(s.vz_up_m_s.size() * sizeof(float)));
  }
  file.commit();
}

std::vector<SectionSnapshot> readSectionSnapshots(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  char magic[8];
  if (!in.read(magic, 8) || std::memcmp(magic, "RVBSECT1", 8) != 0) {
    throw std::runtime_error(path + ": not a railvib section snapshot file");
  }
  SectionSnapshot proto;
  proto.ny_nodes = get<uint64_t>(in, path);
  const uint64_t planes = get<uint64_t>(in, path);
  if (proto.ny_nodes * planes > (uint64_t{1} << 32) || planes > 100000)
    throw std::runtime_error(path + ": bad grid size");
  proto.x_m = get<double>(in, path);
  proto.y0_m = get<double>(in, path);
  proto.dy_m = get<double>(in, path);
  proto.depth_m.resize(planes);
  for (auto& d : proto.depth_m) d = get<double>(in, path);
  const uint64_t count = get<uint64_t>(in, path);
  std::vector<SectionSnapshot> out;
  for (uint64_t c = 0; c < count; ++c) {
    SectionSnapshot s = proto;
    s.index = get<uint64_t>(in, path);
    s.time_s = get<double>(in, path);
    s.vz_up_m_s.resize(s.ny_nodes * planes);
    if (!in.read(reinterpret_cast<char*>(s.vz_up_m_s.data()),
                 static_cast<std::streamsize>(s.vz_up_m_s.size() * sizeof(float)))) {
      throw std::runtime_error(path + ": truncated section snapshot file");
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace railvib::soil
