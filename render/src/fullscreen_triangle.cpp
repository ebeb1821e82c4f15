#include "fullscreen_triangle.hpp"

#include <glm/gtc/matrix_transform.hpp>

namespace forest::render {

glm::mat3 pixelRays(const Camera& camera) {
  using glm::dvec3;
  const glm::dmat4 inverse = glm::inverse(camera.projection() * camera.view() * glm::translate(glm::dmat4(1.0), camera.position));
  const dvec3 forward = camera.forward();
  auto ray = [&](double x, double y) {
    const glm::dvec4 h = inverse * glm::dvec4(x, y, 0.5, 1.0);
    const dvec3 p = dvec3(h) / h.w;
    return p / glm::dot(p, forward);
  };
  const dvec3 centre = ray(0.0, 0.0);
  return glm::mat3(glm::dmat3(ray(1.0, 0.0) - centre, ray(0.0, 1.0) - centre, -centre));
}

gl::Program loadFullScreenProgram(const std::vector<std::string>& fragments, const std::string& defines) {
  std::vector<std::string> files{"fullscreen.vert"};
  files.insert(files.end(), fragments.begin(), fragments.end());
  return gl::loadProgram(files, defines + gl::readShader("frame_block.glsl"));
}

PassImage::PassImage(int width, int height, const char* label, GLenum format) : texture(format, width, height) {
  framebuffer.attach(GL_COLOR_ATTACHMENT0, texture);
  framebuffer.checkComplete(label);
  glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void PassImage::bindForDrawing() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
  glViewport(0, 0, texture.width(), texture.height());
}

void PassImage::attachDepth(const gl::Texture& depth) {
  framebuffer.attach(GL_DEPTH_ATTACHMENT, depth);
  framebuffer.checkComplete("term image with depth");
}

void PassImage::clearToSky() const {
  if (texture.format() == GL_R32UI) {
    const GLuint packed[4] = {0x3C00u, 0u, 0u, 0u};  // packHalf2x16(vec2(1, 0)): 1.0 as a half in the low bits
    glClearNamedFramebufferuiv(framebuffer.id(), GL_COLOR, 0, packed);
  } else {
    const GLfloat sky[4] = {1.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(framebuffer.id(), GL_COLOR, 0, sky);
  }
}

void FullScreenTriangle::draw(const gl::Program& program) const {
  program.use();
  glBindVertexArray(empty_.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

}  // namespace forest::render
