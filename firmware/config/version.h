// The product's version (semantic: major.minor.patch), in one place: the firmware's boot and
// info frames carry it, and every tool's --version prints it. Raise it with each release; the
// build stamps the commit it was made from beside it (cmake/build_identity.cmake).
#pragma once

#include <stdint.h>

namespace wmra {
namespace config {

struct Version {
  uint8_t major, minor, patch;
};
constexpr Version kProductVersion{0, 7, 0};

}  // namespace config
}  // namespace wmra
