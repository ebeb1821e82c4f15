// EGL backend: the EGL device platform when a hardware device exists (a GPU without a display),
// else Mesa's surfaceless platform (llvmpipe). No surface: rendering goes to framebuffer objects.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <fmt/format.h>

#include <string>
#include <vector>

#include "backends.hpp"
#include "forest/core/error.hpp"

namespace forest::gl::detail {
namespace {

std::string eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return fmt::format("EGL error 0x{:04x}", error);
  }
}

[[noreturn]] void fail(const std::string& call) {
  throw Error(fmt::format("{} failed: {}", call, eglErrorName(eglGetError())));
}

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::string all = std::string(" ") + list + " ";
  return all.find(std::string(" ") + name + " ") != std::string::npos;
}

template <typename F>
F proc(const char* name) {
  return reinterpret_cast<F>(eglGetProcAddress(name));
}

struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
};

// A hardware EGL device if the client library offers one, else Mesa surfaceless.
Display openDisplay() {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay = proc<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  if (getPlatformDisplay == nullptr) throw Error("EGL: eglGetPlatformDisplayEXT is missing");

  if (hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
    auto queryDevices = proc<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
    auto queryDeviceString = proc<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
    EGLint count = 0;
    if (queryDevices != nullptr && queryDeviceString != nullptr && queryDevices(0, nullptr, &count) &&
        count > 0) {
      std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
      queryDevices(count, devices.data(), &count);
      for (EGLDeviceEXT device : devices) {
        const char* deviceExtensions = queryDeviceString(device, EGL_EXTENSIONS);
        if (hasExtension(deviceExtensions, "EGL_MESA_device_software")) continue;
        EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
        EGLint major = 0, minor = 0;
        if (display != EGL_NO_DISPLAY && eglInitialize(display, &major, &minor)) {
          return {display, "EGL device"};
        }
      }
    }
  }
  if (!hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
    throw Error("EGL: no hardware device and no EGL_MESA_platform_surfaceless");
  }
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) fail("eglGetPlatformDisplayEXT(surfaceless)");
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) fail("eglInitialize(surfaceless)");
  return {display, "EGL surfaceless (Mesa)"};
}

class EglContext final : public Context {
 public:
  explicit EglContext(const ContextOptions& options) {
    auto [display, platform] = openDisplay();
    display_ = display;
    if (!eglBindAPI(EGL_OPENGL_API)) fail("eglBindAPI(EGL_OPENGL_API)");

    EGLConfig config = nullptr;
    const char* displayExtensions = eglQueryString(display_, EGL_EXTENSIONS);
    if (!hasExtension(displayExtensions, "EGL_KHR_no_config_context")) {
      const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint found = 0;
      if (!eglChooseConfig(display_, configAttributes, &config, 1, &found) || found == 0) {
        fail("eglChooseConfig(OpenGL)");
      }
    }
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4,
                                        EGL_CONTEXT_MINOR_VERSION, 5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_CONTEXT_OPENGL_DEBUG, options.debug ? EGL_TRUE : EGL_FALSE,
                                        EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, contextAttributes);
    if (context_ == EGL_NO_CONTEXT) fail("eglCreateContext(OpenGL 4.5 core)");
    makeCurrent();
    initialiseGl(Backend::Egl, platform, reinterpret_cast<ProcLoader>(eglGetProcAddress), options.debug);
  }

  ~EglContext() override {
    if (display_ != EGL_NO_DISPLAY) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
      // No eglTerminate: the platform display is one per process and shared by every context on
      // it, so terminating it here would pull it from under another live context (and Mesa 22.3
      // leaks JIT state when the driver is unloaded by it).
    }
  }

  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) fail("eglMakeCurrent");
  }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<Context> createEglContext(const ContextOptions& options) {
  return std::make_unique<EglContext>(options);
}

}  // namespace forest::gl::detail
