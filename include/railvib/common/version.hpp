// railvib/common: the version of this build (`git describe --always --dirty --tags` of the source
// tree at build time, "unknown" without git), recorded in every bag and printed by railvib_tool.
#pragma once

namespace railvib {
const char* railvibVersion();
}  // namespace railvib
