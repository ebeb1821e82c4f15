#include "forest/render/prop_renderer.hpp"

#include <algorithm>
#include <array>
#include <ranges>
#include <string>

#include "forest/core/error.hpp"

namespace forest::render {
namespace {

struct CubeVertex {
  float position[3];  // unit cube [0, 1]³
  float normal[3];
};

struct PropInstance {
  float min[4];
  float max[4];
  float albedo[4];
  std::uint32_t objectId;
  std::uint32_t padding[3];
};

// 6 faces × 4 vertices, outward normals, counter-clockwise seen from outside.
std::array<CubeVertex, 24> unitCubeVertices() {
  std::array<CubeVertex, 24> v{};
  const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const float p[6][4][3] = {
      {{1, 0, 1}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
      {{0, 1, 1}, {1, 1, 1}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}}};
  for (int f = 0; f < 6; ++f) {
    for (int k = 0; k < 4; ++k) {
      CubeVertex& c = v[static_cast<size_t>(f * 4 + k)];
      for (int a = 0; a < 3; ++a) {
        c.position[a] = p[f][k][a];
        c.normal[a] = n[f][a];
      }
    }
  }
  return v;
}

std::array<unsigned, 36> unitCubeIndices() {
  std::array<unsigned, 36> idx{};
  for (unsigned f = 0; f < 6; ++f) {
    const unsigned b = f * 4;
    const unsigned quad[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
    for (unsigned k = 0; k < 6; ++k) idx[f * 6 + k] = quad[k];
  }
  return idx;
}

PropInstance propInstance(const PropBox& p, std::uint32_t objectId, const glm::dvec3& origin) {
  // Relative to the view's origin, subtracted in double (DESIGN §4: camera-relative, so a prop
  // 1e5 m from the world origin keeps its millimetres).
  const glm::vec3 min(p.min - origin), max(p.max - origin);
  return {{min.x, min.y, min.z, 1.f}, {max.x, max.y, max.z, 1.f}, {float(p.albedo.x), float(p.albedo.y), float(p.albedo.z), 1.f}, objectId, {0, 0, 0}};
}

}  // namespace

void PropRenderer::update(const std::vector<PropBox>& props) {
  if (props.size() != props_.size())
    throw Error("PropRenderer::update: " + std::to_string(props.size()) + " props, built for " + std::to_string(props_.size()));
  props_ = props;
}

PropRenderer::PropRenderer(const std::vector<PropBox>& props, Output output, std::uint32_t objectIdBase)
    : program_(loadSurfaceProgram("props.vert", "props.frag", output)),
      viewUniforms_(kViewBlockBinding, sizeof(ViewBlock)),
      props_(props),
      objectIdBase_(objectIdBase) {
  const auto vertices = unitCubeVertices();
  const auto indices = unitCubeIndices();
  vertices_ = gl::Buffer(sizeof(vertices), vertices.data(), 0);
  indices_ = gl::Buffer(sizeof(indices), indices.data(), 0);
  // A segment holds every prop (the largest draw), so the ring never grows.
  instances_ = std::make_unique<gl::StreamRing>(std::max<size_t>(1, props.size()) * sizeof(PropInstance), sizeof(PropInstance));

  const GLuint vao = vertexArray_.id();
  glVertexArrayVertexBuffer(vao, 0, vertices_.id(), 0, sizeof(CubeVertex));
  glVertexArrayElementBuffer(vao, indices_.id());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(CubeVertex, position));
  glVertexArrayAttribBinding(vao, 0, 0);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, offsetof(CubeVertex, normal));
  glVertexArrayAttribBinding(vao, 1, 0);
  glVertexArrayVertexBuffer(vao, 1, instances_->id(), 0, sizeof(PropInstance));
  glVertexArrayBindingDivisor(vao, 1, 1);
  for (GLuint attribute = 2; attribute <= 4; ++attribute) {
    glEnableVertexArrayAttrib(vao, attribute);
    glVertexArrayAttribFormat(vao, attribute, 4, GL_FLOAT, GL_FALSE, (attribute - 2) * 4 * sizeof(float));
    glVertexArrayAttribBinding(vao, attribute, 1);
  }
  glEnableVertexArrayAttrib(vao, 5);
  glVertexArrayAttribIFormat(vao, 5, 1, GL_UNSIGNED_INT, offsetof(PropInstance, objectId));
  glVertexArrayAttribBinding(vao, 5, 1);
}

PropRenderer::~PropRenderer() = default;

template <class PropIndices>
long long PropRenderer::drawInstances(const DrawView& view, const PropIndices& props) const {
  // The listed props' boxes written once into the ring, drawn with one instanced call.
  const std::size_t count = std::size(props);
  if (count == 0) return 0;
  const GLuint ringBefore = instances_->id();
  const gl::StreamRing::Allocation part = instances_->allocate(count * sizeof(PropInstance));
  if (instances_->id() != ringBefore) glVertexArrayVertexBuffer(vertexArray_.id(), 1, instances_->id(), 0, sizeof(PropInstance));
  auto* out = static_cast<PropInstance*>(part.data);
  for (std::uint32_t p : props) {
    if (p >= props_.size()) throw Error("PropRenderer::draw: no prop " + std::to_string(p));
    *out++ = propInstance(props_[p], objectIdBase_ + p, view.origin);
  }
  viewUniforms_.bind(viewBlock(view));
  program_.use();
  glBindVertexArray(vertexArray_.id());
  glDrawElementsInstancedBaseInstance(GL_TRIANGLES, 36, GL_UNSIGNED_INT, nullptr, static_cast<GLsizei>(count),
                                      static_cast<GLuint>(part.offset / sizeof(PropInstance)));
  glBindVertexArray(0);
  return 12 * static_cast<long long>(count);
}

long long PropRenderer::draw(const DrawView& view, std::span<const std::uint32_t> props) const {
  return drawInstances(view, props);
}

void PropRenderer::draw(const Camera& camera, const SunSettings& sun) const {
  drawInstances(DrawView::fromCamera(camera, 0.0, sun), std::views::iota(std::uint32_t{0}, static_cast<std::uint32_t>(props_.size())));
}

void drawLitPropScene(const PropRenderer& props, const Camera& camera, const Scene& scene) {
  const glm::vec3 sky(scene.render.sky_color);
  glClearColor(sky.r, sky.g, sky.b, 1.0f);
  glClearDepth(0.0);  // reversed-Z: far = 0
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  props.draw(camera, scene.sun);
}

}  // namespace forest::render
