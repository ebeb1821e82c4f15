// forest info: which GL backend, version and renderer this machine gives, and its limits.
#include <nlohmann/json.hpp>

#include <iostream>

#include "commands.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/gl.hpp"

namespace forest::app {
namespace {

struct InfoOptions {
  GlOptions gl;
  bool json = false;
};

int runInfo(const InfoOptions& options) {
  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::kBackendNames.parse(options.gl.backend);
  contextOptions.visible = false;
  auto context = gl::createContext(contextOptions);
  const gl::ContextInfo& info = context->info();

  auto integer = [](GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
  };
  GLint samplesBits = 0, timestampBits = 0;
  glGetQueryiv(GL_SAMPLES_PASSED, GL_QUERY_COUNTER_BITS, &samplesBits);
  glGetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &timestampBits);
  GLint viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);

  nlohmann::ordered_json j;
  j["backend"] = std::string(gl::kBackendNames.name(info.backend));
  j["platform"] = info.platform;
  j["gl_version"] = info.version;
  j["renderer"] = info.renderer;
  j["vendor"] = info.vendor;
  j["glsl_version"] = info.glsl;
  j["core_profile"] = info.coreProfile;
  j["debug_context"] = info.debugContext;
  j["software_renderer"] = info.softwareRenderer;
  j["limits"] = {{"max_texture_size", integer(GL_MAX_TEXTURE_SIZE)},
                 {"max_viewport", {viewport[0], viewport[1]}},
                 {"max_samples", integer(GL_MAX_SAMPLES)},
                 {"max_color_attachments", integer(GL_MAX_COLOR_ATTACHMENTS)},
                 {"samples_passed_query_bits", samplesBits},
                 {"timestamp_query_bits", timestampBits}};
  j["backends_built_in"] = {"egl", "osmesa", "window"};

  if (options.json) {
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << "backend:   " << gl::describe(info) << "\n"
            << "vendor:    " << info.vendor << "\n"
            << "GLSL:      " << info.glsl << "\n"
            << "profile:   " << (info.coreProfile ? "core" : "compatibility")
            << (info.debugContext ? ", debug" : "") << (info.softwareRenderer ? ", software renderer" : "")
            << "\n"
            << "limits:    max texture " << j["limits"]["max_texture_size"] << ", max viewport " << viewport[0]
            << "x" << viewport[1] << ", samples-passed query " << samplesBits << " bits, timestamp query "
            << timestampBits << " bits\n"
            << "backends:  egl, osmesa, window (built in; choose with --gl)\n";
  return 0;
}

}  // namespace

Run addInfoCommand(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* command = app.add_subcommand("info", "Print the GL backend, version, renderer and limits");
  options->gl.add(*command);
  command->add_flag("--json", options->json, "Print JSON instead of text");
  return [options] { return runInfo(*options); };
}

}  // namespace forest::app
