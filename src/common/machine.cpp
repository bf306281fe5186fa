#include "railvib/common/machine.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

namespace railvib {

namespace {

// A cgroup limit file ("max" or a byte count; cgroup v1 writes a huge number for "no limit").
double cgroupLimitBytes(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return 0.0;
  try {
    const double v = std::stod(text);
    return v > 0.0 && v < 1e18 ? v : 0.0;
  } catch (const std::exception&) {
    return 0.0;
  }
}

}  // namespace

double machineMemoryBytes() {
  double total = 0.0;
  std::ifstream in("/proc/meminfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("MemTotal:", 0) == 0) {
      std::istringstream s(line.substr(9));
      double kb = 0.0;
      if (s >> kb) total = kb * 1024.0;
      break;
    }
  }
  for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const double limit = cgroupLimitBytes(path);
    if (limit > 0.0) total = total > 0.0 ? std::min(total, limit) : limit;
  }
  return total;
}

}  // namespace railvib
