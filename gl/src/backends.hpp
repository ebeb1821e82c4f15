#pragma once
// Backend factories (internal). Each returns a current context or throws forest::Error.
#include "forest/gl/context.hpp"

namespace forest::gl::detail {

std::unique_ptr<Context> createEglContext(const ContextOptions& options);
std::unique_ptr<Context> createOSMesaContext(const ContextOptions& options);
std::unique_ptr<Context> createWindowContext(const ContextOptions& options);

}  // namespace forest::gl::detail
