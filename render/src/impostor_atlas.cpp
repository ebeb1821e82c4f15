#include "forest/render/impostor_atlas.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "forest/gl/shader.hpp"

namespace forest::render {
namespace {

using vegetation::kSpeciesCount;

struct BakeVertex {
  glm::vec3 position, normal, albedo;
};

// LOD0 of a species in buffers the bake draws from.
struct BakeMesh {
  gl::Buffer vertices, indices;
  gl::VertexArray vertexArray;
  GLsizei indexCount = 0;

  explicit BakeMesh(const vegetation::TreeMesh& mesh) {
    std::vector<BakeVertex> v(mesh.positions.size());
    for (size_t k = 0; k < v.size(); ++k) v[k] = {mesh.positions[k], mesh.normals[k], mesh.albedo[k]};
    vertices = gl::Buffer(v.size() * sizeof(BakeVertex), v.data(), 0);
    indices = gl::Buffer(mesh.indices.size() * sizeof(std::uint32_t), mesh.indices.data(), 0);
    indexCount = static_cast<GLsizei>(mesh.indices.size());
    const GLuint vao = vertexArray.id();
    glVertexArrayVertexBuffer(vao, 0, vertices.id(), 0, sizeof(BakeVertex));
    glVertexArrayElementBuffer(vao, indices.id());
    for (GLuint a = 0; a < 3; ++a) {
      glEnableVertexArrayAttrib(vao, a);
      glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, a * sizeof(glm::vec3));
      glVertexArrayAttribBinding(vao, a, 0);
    }
  }
};

}  // namespace

ImpostorTexel unpackImpostorTexel(const glm::uvec4& packed) {
  ImpostorTexel t;
  t.covered = (packed.y >> 24) != 0u;
  if (!t.covered) return t;
  t.front = std::bit_cast<float>(packed.x);
  t.back = std::bit_cast<float>(packed.w);
  for (int c = 0; c < 3; ++c) {
    t.albedo[c] = ((packed.y >> (8 * c)) & 0xffu) / 255.0;
    t.normal[c] = ((packed.z >> (10 * c)) & 0x3ffu) / 1023.0 * 2.0 - 1.0;
  }
  return t;
}

ImpostorAtlas::ImpostorAtlas(const vegetation::Forest& forest, int views, int texels) : grid_(views), texels_(texels) {
  const auto start = std::chrono::steady_clock::now();
  const int side = views * texels;
  texture_ = gl::Texture(GL_RGBA32UI, side, side, 1, kSpeciesCount);
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) glTextureParameteri(texture_.id(), p, GL_NEAREST);
  const gl::Program program = gl::loadProgram({"impostor_bake.vert", "impostor_bake.frag"});
  std::vector<glm::uvec4> layer;
  for (int s = 0; s < kSpeciesCount; ++s) {
    const vegetation::SpeciesModel& model = forest.species()[static_cast<size_t>(s)];
    spheres_[static_cast<size_t>(s)] = vegetation::impostorSphere(model);
    layer.assign(static_cast<size_t>(side) * side, glm::uvec4(0u));
    if (model.lods[0].indices.empty() || spheres_[static_cast<size_t>(s)].radius <= 0.0) continue;
    bakeSpecies(model, program, layer);
    glTextureSubImage3D(texture_.id(), 0, 0, 0, s, side, side, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT, layer.data());
  }
  ImpostorBlock block;
  block.grid = glm::ivec4(views, texels, 0, 0);
  static_assert(kSpeciesCount <= 4 && vegetation::kQuerySlabs == 4 && vegetation::kCasterSlabs == 8, "impostor.glsl's array sizes");
  for (vegetation::Species species : vegetation::kAllSpecies) {
    const auto s = static_cast<size_t>(species);
    const vegetation::SpeciesModel& model = forest.model(species);
    Aabb box;
    for (const vegetation::TreeMesh& lod : model.lods) box.extend(lod.bounds);
    if (!box.valid()) box.extend(glm::dvec3(0.0));
    block.sphere[s] = glm::vec4(glm::vec3(spheres_[s].centre), static_cast<float>(spheres_[s].radius));
    block.boxMin[s] = glm::vec4(glm::vec3(box.min), 0.0f);
    block.boxMax[s] = glm::vec4(glm::vec3(box.max), 0.0f);
    const std::vector<vegetation::CrownSlab>& query = forest.querySlabs(species);
    for (size_t k = 0; k < query.size() && k < 4; ++k)
      block.querySlabs[s * 4 + k] = glm::vec4(query[k].bottom, query[k].top, query[k].radius, 0.0);
    const std::vector<vegetation::CrownSlab>& caster = forest.casterSlabs(species);
    for (size_t k = 0; k < 8; ++k)
      block.casterSlabs[s * 8 + k] = k < caster.size() ? glm::vec4(caster[k].bottom, caster[k].top, caster[k].radiusBottom, caster[k].radiusTop)
                                                       : glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);  // empty
  }
  block_ = gl::Buffer(sizeof block, &block, 0);
  bakeSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void ImpostorAtlas::bakeSpecies(const vegetation::SpeciesModel& model, const gl::Program& program,
                                std::vector<glm::uvec4>& layer) const {
  const int side = grid_.views() * texels_;
  const vegetation::ImpostorSphere& sphere = spheres_[static_cast<size_t>(model.species)];
  const BakeMesh mesh(model.lods[0]);
  gl::Texture surface(GL_RGBA32UI, side, side), depth(GL_DEPTH_COMPONENT32F, side, side);
  gl::Framebuffer target;
  target.attach(GL_COLOR_ATTACHMENT0, surface);
  target.attach(GL_DEPTH_ATTACHMENT, depth);
  target.checkComplete("impostor bake");
  program.set("uCentreRadius", glm::vec4(glm::vec3(sphere.centre), static_cast<float>(sphere.radius)));
  program.set("uRadius", static_cast<float>(sphere.radius));

  glBindFramebuffer(GL_FRAMEBUFFER, target.id());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_CULL_FACE);
  program.use();
  glBindVertexArray(mesh.vertexArray.id());
  // Pass 1 draws the faces turned to the viewer (the surface it sees), pass 2 those turned away
  // (with the nearest, the surface a backside shadow map stores: Scherzer 2006 §5.1).
  std::vector<float> back(static_cast<size_t>(side) * side);
  for (GLenum culled : {GL_BACK, GL_FRONT}) {
    const GLuint nothing[4] = {0, 0, 0, 0};
    const float far = 1.0f;
    glClearBufferuiv(GL_COLOR, 0, nothing);
    glClearBufferfv(GL_DEPTH, 0, &far);
    glCullFace(culled);
    glColorMaski(0, culled == GL_BACK, culled == GL_BACK, culled == GL_BACK, culled == GL_BACK);
    for (int i = 0; i < grid_.views(); ++i)
      for (int j = 0; j < grid_.views(); ++j) {
        const vegetation::ImpostorFrame f = grid_.frame(i, j);
        program.set("uRight", glm::vec3(f.right));
        program.set("uUp", glm::vec3(f.up));
        program.set("uToViewer", glm::vec3(f.toViewer));
        glViewport(i * texels_, j * texels_, texels_, texels_);
        glDrawElements(GL_TRIANGLES, mesh.indexCount, GL_UNSIGNED_INT, nullptr);
      }
    if (culled == GL_BACK)
      glGetTextureImage(surface.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(layer.size() * sizeof(glm::uvec4)),
                        layer.data());
    else
      glGetTextureImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(back.size() * sizeof(float)), back.data());
  }
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glCullFace(GL_BACK);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const double toMetres = 2.0 * sphere.radius;
  for (size_t k = 0; k < layer.size(); ++k)
    if ((layer[k].y >> 24) != 0u) layer[k].w = std::bit_cast<std::uint32_t>(static_cast<float>(back[k] * toMetres));
}

double ImpostorAtlas::largestError() const {
  const double parallax = std::sin(grid_.largestAngle());
  double largest = 0.0;
  for (const vegetation::ImpostorSphere& sphere : spheres_)
    largest = std::max({largest, 2.0 * sphere.radius / texels_, sphere.radius * parallax});
  return largest;
}

double ImpostorAtlas::switchDistance(double fovy, int heightPixels) const {
  // A pixel at distance d spans d · 2 tan(fovy / 2) / height.
  return largestError() * heightPixels / (2.0 * std::tan(fovy / 2.0));
}

void ImpostorAtlas::bind() const {
  glBindTextureUnit(kImpostorAtlasUnit, texture_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, kImpostorBlockBinding, block_.id());
}

glm::dvec3 ImpostorAtlas::bakePoint(vegetation::Species species, int i, int j, const glm::dvec2& texel, double s) const {
  const vegetation::ImpostorSphere& sphere = spheres_[static_cast<size_t>(species)];
  const vegetation::ImpostorFrame f = grid_.frame(i, j);
  const double r = sphere.radius;
  const double a = (2.0 * texel.x / texels_ - 1.0) * r, b = (2.0 * texel.y / texels_ - 1.0) * r;
  return sphere.centre + a * f.right + b * f.up + (r - s) * f.toViewer;
}

std::vector<glm::uvec4> ImpostorAtlas::download(vegetation::Species species) const {
  const int side = texture_.width();
  std::vector<glm::uvec4> layer(static_cast<size_t>(side) * side);
  glGetTextureSubImage(texture_.id(), 0, 0, 0, static_cast<int>(species), side, side, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                       static_cast<GLsizei>(layer.size() * sizeof(glm::uvec4)), layer.data());
  return layer;
}

}  // namespace forest::render
