// OSMesa backend, loaded with dlopen so the binary neither links libOSMesa next to libEGL/libGL
// (their GL symbols clash, DESIGN §3) nor fails to start on Mesa ≥ 25.1, which removed it.
#include <GL/osmesa.h>
#include <dlfcn.h>
#include <fmt/format.h>

#include <vector>

#include "backends.hpp"
#include "forest/core/error.hpp"

namespace forest::gl::detail {
namespace {

constexpr const char* kLibraryNames[] = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};

struct OSMesaApi {
  void* library = nullptr;
  decltype(&OSMesaCreateContextAttribs) createContextAttribs = nullptr;
  decltype(&OSMesaMakeCurrent) makeCurrent = nullptr;
  decltype(&OSMesaDestroyContext) destroyContext = nullptr;
  decltype(&OSMesaGetProcAddress) getProcAddress = nullptr;
};

OSMesaApi loadApi() {
  OSMesaApi api;
  std::string errors;
  for (const char* name : kLibraryNames) {
    api.library = dlopen(name, RTLD_NOW | RTLD_LOCAL);
    if (api.library != nullptr) break;
    errors += fmt::format(" {};", dlerror());
  }
  if (api.library == nullptr) throw Error("OSMesa: cannot load libOSMesa:" + errors);
  auto symbol = [&](const char* name) {
    void* p = dlsym(api.library, name);
    if (p == nullptr) throw Error(fmt::format("OSMesa: symbol {} missing", name));
    return p;
  };
  api.createContextAttribs =
      reinterpret_cast<decltype(api.createContextAttribs)>(symbol("OSMesaCreateContextAttribs"));
  api.makeCurrent = reinterpret_cast<decltype(api.makeCurrent)>(symbol("OSMesaMakeCurrent"));
  api.destroyContext = reinterpret_cast<decltype(api.destroyContext)>(symbol("OSMesaDestroyContext"));
  api.getProcAddress = reinterpret_cast<decltype(api.getProcAddress)>(symbol("OSMesaGetProcAddress"));
  return api;
}

// OSMesaGetProcAddress through the dlopen'ed library (glad wants a plain function pointer).
OSMesaApi* gApi = nullptr;
void (*getProc(const char* name))() { return reinterpret_cast<void (*)()>(gApi->getProcAddress(name)); }

class OSMesaBackendContext final : public Context {
 public:
  explicit OSMesaBackendContext(const ContextOptions& options) : api_(loadApi()) {
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    context_ = api_.createContextAttribs(attributes, nullptr);
    if (context_ == nullptr) throw Error("OSMesaCreateContextAttribs(OpenGL 4.5 core) failed");
    // Rendering goes to framebuffer objects; the OSMesa buffer is a 1×1 placeholder.
    buffer_.resize(4);
    makeCurrent();
    gApi = &api_;
    initialiseGl(Backend::OSMesa, "OSMesa", getProc, options.debug);
  }

  ~OSMesaBackendContext() override {
    if (context_ != nullptr) api_.destroyContext(context_);
    if (gApi == &api_) gApi = nullptr;
    // The library stays loaded: Mesa registers atexit handlers that must not be unmapped.
  }

  void makeCurrent() override {
    if (!api_.makeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1)) {
      throw Error("OSMesaMakeCurrent failed");
    }
  }

 private:
  OSMesaApi api_;
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> buffer_;
};

}  // namespace

std::unique_ptr<Context> createOSMesaContext(const ContextOptions& options) {
  return std::make_unique<OSMesaBackendContext>(options);
}

}  // namespace forest::gl::detail
