// railvib/common: what the machine running a scenario offers (for checks made before allocating).
#pragma once

namespace railvib {

/// Memory this process may use, in bytes: the machine's total memory (MemTotal of /proc/meminfo),
/// or the cgroup's memory limit if lower; 0 when neither can be read.
double machineMemoryBytes();

}  // namespace railvib
