#include "forest/render/draw_view.hpp"

#include <glm/gtc/matrix_transform.hpp>

namespace forest::render {

DrawView DrawView::fromCamera(const Camera& camera, double time, const SunSettings& sun) {
  DrawView v;
  v.viewProjectionRelative = camera.projection() * camera.view() * glm::translate(glm::dmat4(1.0), camera.position);
  v.origin = camera.position;
  v.lodEye = camera.position;
  v.time = time;
  v.sun = sun;
  return v;
}

ViewBlock viewBlock(const DrawView& view) {
  ViewBlock b;
  b.viewProjectionRelative = glm::mat4(view.viewProjectionRelative);
  b.lightDepthRow = glm::vec4(view.lightDepthRelative);
  b.toSunAmbient = glm::vec4(glm::vec3(-view.sun.direction), static_cast<float>(view.sun.ambient));
  b.sunColorSlopeBias = glm::vec4(glm::vec3(view.sun.color), static_cast<float>(view.depthSlopeBias));
  b.viewer = view.fromSun ? glm::vec4(1.0f, 1.0f, 0.0f, 0.0f) : glm::vec4(0.0f, -1.0f, 0.0f, 0.0f);
  return b;
}

gl::Program loadSurfaceProgram(const std::string& vertex, const std::string& fragment, SurfaceOutput output,
                               const std::string& defines) {
  const std::string extraDefines = defines + gl::readShader("view_block.glsl");
  switch (output) {
    case SurfaceOutput::ObjectId: return gl::loadProgram({vertex, fragment}, "#define OUTPUT_ID 1\n" + extraDefines);
    case SurfaceOutput::GBuffer:
      return gl::loadProgram({vertex, fragment, "gbuffer.frag"}, "#define OUTPUT_GBUFFER 1\n" + extraDefines);
    case SurfaceOutput::LightDepth:
      return gl::loadProgram({vertex, fragment, "light_depth.frag"}, "#define OUTPUT_LIGHT_DEPTH 1\n" + extraDefines);
    case SurfaceOutput::QueryStamp:
      return gl::loadProgram({vertex, fragment, "query_stamp.frag"},
                             "#define OUTPUT_QUERY_STAMP 1\n" + extraDefines + gl::readShader("query_block.glsl"));
    case SurfaceOutput::Lit: break;
  }
  return gl::loadProgram({vertex, fragment}, extraDefines);
}

}  // namespace forest::render
