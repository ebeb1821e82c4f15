// GLFW window backend (interactive walkthrough; tests run it under xvfb-run).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include "backends.hpp"
#include "forest/core/error.hpp"

namespace forest::gl::detail {
namespace {

std::string lastGlfwError() {
  const char* description = nullptr;
  const int code = glfwGetError(&description);
  return code == GLFW_NO_ERROR ? "no GLFW error reported" : (description ? description : "unknown");
}

class WindowContext final : public Context {
 public:
  explicit WindowContext(const ContextOptions& options) {
    if (!glfwInit()) throw Error("GLFW: glfwInit failed (no display? use xvfb-run): " + lastGlfwError());
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
    window_ = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
    if (window_ == nullptr) {
      const std::string why = lastGlfwError();
      glfwTerminate();
      throw Error("GLFW: cannot create a 4.5 core window: " + why);
    }
    makeCurrent();
    initialiseGl(Backend::Window, "GLFW", glfwGetProcAddress, options.debug);
  }

  ~WindowContext() override {
    if (window_ != nullptr) glfwDestroyWindow(window_);
    glfwTerminate();
  }

  void makeCurrent() override { glfwMakeContextCurrent(window_); }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  GLFWwindow* window() override { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace

std::unique_ptr<Context> createWindowContext(const ContextOptions& options) {
  return std::make_unique<WindowContext>(options);
}

}  // namespace forest::gl::detail
