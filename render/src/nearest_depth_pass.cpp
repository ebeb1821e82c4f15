#include "nearest_depth_pass.hpp"

#include <bit>
#include <cstdint>

namespace forest::render {

NearestDepthPass::NearestDepthPass() : program_(gl::loadProgram({"nearest_depth.comp"})) {
  for (gl::Buffer& b : buffers_) b = gl::Buffer(sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

double NearestDepthPass::read(int buffer, const Camera& camera) const {
  std::uint32_t bits = 0;
  glGetNamedBufferSubData(buffers_[static_cast<size_t>(buffer)].id(), 0, sizeof bits, &bits);
  const double d = std::bit_cast<float>(bits);
  if (!(d > 0.0)) return 0.0;
  return camera.eyeDepthOfReversedZ(d);  // shadow_lookup.frag's eyeDepth
}

std::optional<double> NearestDepthPass::run(const gl::Texture& depth, const Camera& camera) {
  const int current = next_;
  const GLuint zero = 0;
  glClearNamedBufferData(buffers_[static_cast<size_t>(current)].id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers_[static_cast<size_t>(current)].id());
  glBindTextureUnit(5, depth.id());
  program_.use();
  glDispatchCompute(static_cast<GLuint>((depth.width() + 31) / 32), static_cast<GLuint>((depth.height() + 31) / 32), 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glBindTextureUnit(5, 0);
  next_ = 1 - current;
  const int source = havePrevious_ ? 1 - current : current;
  havePrevious_ = true;
  const double z = read(source, camera);
  if (z > 0.0) return z;
  return std::nullopt;
}

}  // namespace forest::render
