#include "forest/core/error.hpp"

#include <cerrno>
#include <cstring>

namespace forest {

std::string systemErrorMessage(const std::string& what) {
  return what + ": " + std::strerror(errno);
}

}  // namespace forest
