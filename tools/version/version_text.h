// Every tool's --version line: the product's version (firmware/config/version.h) and the commit
// this build was made from (build_identity.h, cmake/build_identity.cmake), e.g.
//   armkin 0.7.0 (commit 85e4ee73d90a, with changes)
#pragma once

#include <string>

#include "build_identity.h"
#include "config/version.h"

namespace wmra {

inline std::string version_text(const char* tool) {
  const config::Version v = config::kProductVersion;
  std::string s = std::string(tool) + " " + std::to_string(v.major) + "." + std::to_string(v.minor) + "." + std::to_string(v.patch);
  if (WMRA_BUILD_FLAGS & 2) return s + " (not built from a git checkout)";
  return s + " (commit " + WMRA_BUILD_COMMIT_HEX + ((WMRA_BUILD_FLAGS & 1) ? ", with changes)" : ")");
}

}  // namespace wmra
