#pragma once
// Draws the scene's props (boxes) with one instanced draw per call, lit by the sun: Lambert diffuse
// plus a weak global ambient (thesis §6.2, without shadows yet). Each draw writes its boxes,
// relative to the view's origin, into a persistently mapped ring (DESIGN §9).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"
#include "forest/gl/stream_ring.hpp"
#include "forest/gl/uniform_stream.hpp"
#include "forest/render/draw_view.hpp"

namespace forest::render {

class PropRenderer {
 public:
  // Lit, ObjectId (objectIdBase + prop index to a GL_R32UI target) or GBuffer.
  using Output = SurfaceOutput;
  explicit PropRenderer(const std::vector<PropBox>& props, Output output = Output::Lit, std::uint32_t objectIdBase = 1);
  ~PropRenderer();
  // Uploads moved props (same count as at construction).
  void update(const std::vector<PropBox>& props);

  // Draws into the bound framebuffer (depth test GL_GREATER: reversed-Z).
  void draw(const Camera& camera, const SunSettings& sun) const;
  // Draws only the given props (indices) from any view; returns the triangles drawn.
  long long draw(const DrawView& view, std::span<const std::uint32_t> props) const;
  int triangleCount() const { return 12 * static_cast<int>(props_.size()); }

 private:
  gl::Program program_;
  mutable gl::UniformStream viewUniforms_;  // ViewBlock at binding 0
  gl::VertexArray vertexArray_;
  gl::Buffer vertices_;
  gl::Buffer indices_;
  std::unique_ptr<gl::StreamRing> instances_;  // each draw's boxes, relative to its view's origin
  std::vector<PropBox> props_;
  std::uint32_t objectIdBase_ = 1;
  template <class PropIndices>
  long long drawInstances(const DrawView& view, const PropIndices& props) const;
};

// Clears the bound framebuffer to `sky` with reversed-Z depth 0 and draws the props.
void drawLitPropScene(const PropRenderer& props, const Camera& camera, const Scene& scene);

}  // namespace forest::render
