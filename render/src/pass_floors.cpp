#include "pass_floors.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

namespace forest::render {

namespace {
gl::Program floorProgram(int reads) {
  return loadFullScreenProgram({"pass_floor.frag", "gbuffer_read.frag"}, "#define FLOOR_READS " + std::to_string(reads) + "\n");
}
}  // namespace

// The targets are RGBA8 like the lighting's colour (the floors write a colour).
PassFloors::PassFloors(int width, int height)
    : full_(width, height, "pass floor", GL_RGBA8),
      half_((width + 1) / 2, (height + 1) / 2, "pass floor", GL_RGBA8),
      packedTerm_(GL_R32UI, (width + 1) / 2, (height + 1) / 2),
      term_(GL_RG16F, (width + 1) / 2, (height + 1) / 2),
      programs_{floorProgram(0), floorProgram(1), floorProgram(2), floorProgram(3), floorProgram(4), floorProgram(5), floorProgram(6)} {
  for (const gl::Texture* t : {&packedTerm_, &term_}) {
    glTextureParameteri(t->id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t->id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  const GLuint zero[2] = {0, 0};
  glClearTexImage(packedTerm_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, zero);
  const float zeros[2] = {0.0f, 0.0f};
  glClearTexImage(term_.id(), 0, GL_RG, GL_FLOAT, zeros);
}

double PassFloors::timeOne(const gl::Program& program, const PassImage& target, int repeats) const {
  std::vector<double> ms;
  for (int i = 0; i < repeats; ++i) {
    glFinish();
    const auto start = std::chrono::steady_clock::now();
    target.bindForDrawing();
    triangle_.draw(program);
    glFinish();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
  return ms[ms.size() / 2];
}

PassFloorTimes PassFloors::time(const GBuffer& gbuffer, const gl::Texture& shadowMap, int repeats) {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glBindTextureUnit(5, gbuffer.surface.id());  // shaders/gbuffer_read.frag
  glBindTextureUnit(4, packedTerm_.id());
  glBindTextureUnit(0, term_.id());
  glBindTextureUnit(3, shadowMap.id());
  PassFloorTimes t;
  t.emptyMs = timeOne(programs_[0], full_, repeats);
  t.gbufferMs = timeOne(programs_[1], full_, repeats);
  t.gbufferAndTermMs = timeOne(programs_[2], full_, repeats);
  t.gbufferBlocksMs = timeOne(programs_[3], half_, repeats);
  t.termTapsMs = timeOne(programs_[4], half_, repeats);
  t.gbufferBlocksAndMapMs = timeOne(programs_[5], half_, repeats);
  t.gbufferAndMapMs = timeOne(programs_[6], full_, repeats);
  glBindTextureUnit(0, 0);
  glBindTextureUnit(3, 0);
  glBindTextureUnit(4, 0);
  glBindTextureUnit(5, 0);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  return t;
}

}  // namespace forest::render
