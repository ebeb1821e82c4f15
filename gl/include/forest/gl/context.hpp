#pragma once
// GL 4.5 core contexts behind one interface. Backends:
//   egl    — EGL device platform on a GPU, else Mesa surfaceless (llvmpipe): the default headless path
//   osmesa — Mesa's off-screen library, loaded at run time (fallback; removed in Mesa 25.1)
//   window — a GLFW window (needs a display; tests use xvfb-run)
//   auto   — egl, then osmesa if egl fails
// Headless contexts have no default framebuffer: render into gl::Framebuffer objects.
// Every context is set to the engine's depth convention: glClipControl(GL_LOWER_LEFT,
// GL_ZERO_TO_ONE) (reversed-Z float depth, see core/camera.hpp).
#include <memory>
#include <string>
#include <string_view>

#include "forest/core/enum_names.hpp"

struct GLFWwindow;

namespace forest::gl {

enum class Backend { Auto, Egl, OSMesa, Window };

inline constexpr EnumNames<Backend, 4> kBackendNames{
    "GL backend", {{{Backend::Auto, "auto"}, {Backend::Egl, "egl"}, {Backend::OSMesa, "osmesa"}, {Backend::Window, "window"}}}};

struct ContextOptions {
  Backend backend = Backend::Auto;
  int width = 640;   // window size (window backend)
  int height = 480;
  bool debug = true;  // ask for a KHR_debug context and route its messages to the log
  bool visible = true;
  std::string title = "forest";
};

struct ContextInfo {
  Backend backend = Backend::Auto;
  std::string platform;  // e.g. "EGL surfaceless (Mesa)", "EGL device", "OSMesa", "GLFW/X11"
  std::string version;   // GL_VERSION
  std::string renderer;  // GL_RENDERER
  std::string vendor;    // GL_VENDOR
  std::string glsl;      // GL_SHADING_LANGUAGE_VERSION
  int major = 0;
  int minor = 0;
  bool coreProfile = false;
  bool debugContext = false;
  bool softwareRenderer = false;  // llvmpipe / softpipe / swrast
};

class Context {
 public:
  virtual ~Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const ContextInfo& info() const { return info_; }
  virtual void makeCurrent() = 0;
  virtual void swapBuffers() {}
  virtual GLFWwindow* window() { return nullptr; }

 protected:
  Context() = default;
  // Called by each backend once its context is current: loads GL through `getProcAddress`,
  // checks for 4.5 core, fills info(), sets the clip convention and debug output.
  using ProcLoader = void (*(*)(const char*))();
  void initialiseGl(Backend backend, std::string platform, ProcLoader getProcAddress, bool debug);

 private:
  ContextInfo info_;
};

// Creates a context and makes it current; throws forest::Error saying why each tried backend failed.
std::unique_ptr<Context> createContext(const ContextOptions& options);

// One line: "backend (platform): GL version, renderer".
std::string describe(const ContextInfo& info);

}  // namespace forest::gl
