#pragma once
// What the full-screen passes (shadow term, blur, lighting) share: one triangle over the viewport
// whose positions and pixel rays shaders/fullscreen.vert makes from gl_VertexID, so there is no
// vertex data — an empty vertex array; the term's image.
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "forest/core/camera.hpp"
#include "forest/gl/objects.hpp"
#include "forest/gl/shader.hpp"

namespace forest::render {

// The frame block's rays (shaders/fullscreen.vert): A with A·(x_ndc, y_ndc, −1) = the camera-relative direction
// through that pixel scaled to eye depth 1 (the position of a pixel at eye depth z is z times it).
glm::mat3 pixelRays(const Camera& camera);

// fullscreen.vert linked with `fragments`, every stage declaring the frame block (frame_block.glsl)
// after `defines` (lines such as "#define X\n").
gl::Program loadFullScreenProgram(const std::vector<std::string>& fragments, const std::string& defines = "");

// An image a full-screen pass writes: its texture (nearest filtering, clamped at the edges for the
// upsample's gathers) and framebuffer. For the shadow term and its eye depth: RG16F (r: term, g:
// eye depth), or R32UI with the two as halves (packHalf2x16: the upsample reads four texels' terms
// and depths with one gather).
struct PassImage {
  PassImage(int width, int height, const char* label, GLenum format = GL_RG16F);
  // Binds its framebuffer and viewport.
  void bindForDrawing() const;
  // Attaches `depth` (its size) as the depth buffer the pass tests against.
  void attachDepth(const gl::Texture& depth);
  // Clears it to the sky's term, 1 at eye depth 0 (RG16F (1, 0); R32UI packHalf2x16(1, 0)).
  void clearToSky() const;
  gl::Texture texture;
  gl::Framebuffer framebuffer;
};

class FullScreenTriangle {
 public:
  // Draws the triangle with `program` into the bound framebuffer.
  void draw(const gl::Program& program) const;

 private:
  gl::VertexArray empty_;
};

}  // namespace forest::render
