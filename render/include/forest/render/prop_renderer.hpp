#pragma once
// Draws the scene's props (boxes) with one instanced draw, lit by the sun: Lambert diffuse plus a
// weak global ambient (thesis §6.2, without shadows yet).
#include <cstdint>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/draw_view.hpp"

namespace forest::render {

class PropRenderer {
 public:
  // Lit, ObjectId (objectIdBase + prop index to a GL_R32UI target) or GBuffer.
  using Output = SurfaceOutput;
  explicit PropRenderer(const std::vector<PropBox>& props, Output output = Output::Lit, std::uint32_t objectIdBase = 1);
  // Uploads moved props (same count as at construction).
  void update(const std::vector<PropBox>& props);

  // Draws into the bound framebuffer (depth test GL_GREATER: reversed-Z).
  void draw(const Camera& camera, const SunSettings& sun) const;
  // Draws only the given props (indices) from any view; returns the triangles drawn.
  long long draw(const DrawView& view, std::span<const std::uint32_t> props) const;
  int triangleCount() const { return 12 * instanceCount_; }

 private:
  gl::Program program_;
  gl::VertexArray vertexArray_;
  gl::Buffer vertices_;
  gl::Buffer indices_;
  mutable gl::Buffer instances_;  // the boxes relative to uploadedOrigin_
  std::vector<PropBox> props_;
  int instanceCount_ = 0;
  std::uint32_t objectIdBase_ = 1;
  mutable bool uploaded_ = false;
  mutable glm::dvec3 uploadedOrigin_{0.0};
  void uploadRelativeTo(const glm::dvec3& origin) const;
  void setUniforms(const DrawView& view) const;
};

// Clears the bound framebuffer to `sky` with reversed-Z depth 0 and draws the props.
void drawLitPropScene(const PropRenderer& props, const Camera& camera, const Scene& scene);

}  // namespace forest::render
