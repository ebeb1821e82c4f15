#include "forest/gl/context.hpp"

#include <fmt/format.h>

#include <cstring>

#include "backends.hpp"
#include "forest/core/error.hpp"
#include "forest/core/log.hpp"
#include "forest/gl/debug.hpp"
#include "forest/gl/gl.hpp"

namespace forest::gl {

void checkError(const char* what) {
  GLenum first = GL_NO_ERROR;
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
    if (first == GL_NO_ERROR) first = e;
  }
  if (first != GL_NO_ERROR) throw Error(fmt::format("GL error 0x{:04x} after {}", first, what));
}

std::string describe(const ContextInfo& info) {
  return fmt::format("{} ({}): OpenGL {} — {}", kBackendNames.name(info.backend), info.platform, info.version,
                     info.renderer);
}

namespace {
std::string glString(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s != nullptr ? s : "";
}
}  // namespace

void Context::initialiseGl(Backend backend, std::string platform, ProcLoader getProcAddress, bool debug) {
  const int version = gladLoadGL(getProcAddress);
  if (version == 0) throw Error(fmt::format("{}: loading GL functions failed", platform));
  info_.backend = backend;
  info_.platform = std::move(platform);
  info_.version = glString(GL_VERSION);
  info_.renderer = glString(GL_RENDERER);
  info_.vendor = glString(GL_VENDOR);
  info_.glsl = glString(GL_SHADING_LANGUAGE_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &info_.major);
  glGetIntegerv(GL_MINOR_VERSION, &info_.minor);
  GLint profile = 0, flags = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
  info_.coreProfile = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  info_.debugContext = (flags & GL_CONTEXT_FLAG_DEBUG_BIT) != 0;
  for (const char* software : {"llvmpipe", "softpipe", "swrast", "SWR"}) {
    if (info_.renderer.find(software) != std::string::npos) info_.softwareRenderer = true;
  }
  if (info_.major * 10 + info_.minor < 45 || !info_.coreProfile) {
    throw Error(fmt::format("{}: got OpenGL {} ({}), need a 4.5 core profile", info_.platform, info_.version,
                            info_.coreProfile ? "core" : "not core"));
  }
  if (debug) enableDebugOutput();
  // The engine's single depth convention (DESIGN §4 clip control): zero-to-one clip depth.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  checkError("glClipControl");
}

std::unique_ptr<Context> createContext(const ContextOptions& options) {
  switch (options.backend) {
    case Backend::Egl: return detail::createEglContext(options);
    case Backend::OSMesa: return detail::createOSMesaContext(options);
    case Backend::Window: return detail::createWindowContext(options);
    case Backend::Auto: break;
  }
  try {
    return detail::createEglContext(options);
  } catch (const Error& eglFailure) {
    log::warn("EGL unavailable ({}); falling back to OSMesa", eglFailure.what());
    try {
      return detail::createOSMesaContext(options);
    } catch (const Error& osmesaFailure) {
      throw Error(fmt::format("no headless GL context: EGL: {}; OSMesa: {}", eglFailure.what(),
                              osmesaFailure.what()));
    }
  }
}

}  // namespace forest::gl
