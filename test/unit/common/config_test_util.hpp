// Shared helpers of the common (configuration) unit tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace railvib::testing {

/// Write `text` to dir/name (creating dir) and return the path.
inline std::filesystem::path writeFile(const std::filesystem::path& dir, const std::string& name,
                                       const std::string& text) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

}  // namespace railvib::testing
