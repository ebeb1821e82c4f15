#include "forest/render/tree_renderer.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>

#include "forest/core/frustum.hpp"
#include "gpu_caster_filter.hpp"

namespace forest::render {
namespace {

using vegetation::kSpeciesCount;
using vegetation::kTreeLods;

struct TreeVertex {
  glm::vec3 position, normal, albedo;
};

}  // namespace

TreeRenderer::TreeRenderer(const vegetation::Forest& forest, Output output, std::uint32_t objectIdBase)
    : forest_(forest),
      output_(output),
      objectIdBase_(objectIdBase),
      program_(loadSurfaceProgram("trees.vert", "trees.frag", output)),
      viewUniforms_(kViewBlockBinding, sizeof(ViewBlock)) {
  std::vector<TreeVertex> vertices;
  std::vector<std::uint32_t> indices;
  auto append = [&](const vegetation::TreeMesh& mesh, Range& range) {
    range.baseVertex = static_cast<int>(vertices.size());
    range.firstIndex = static_cast<int>(indices.size());
    range.indexCount = static_cast<int>(mesh.indices.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) vertices.push_back({mesh.positions[v], mesh.normals[v], mesh.albedo[v]});
    indices.insert(indices.end(), mesh.indices.begin(), mesh.indices.end());
  };
  for (int s = 0; s < kSpeciesCount; ++s) {
    for (int lod = 0; lod < kTreeLods; ++lod) append(forest.species()[s].lods[lod], ranges_[s][lod]);
    append(forest.species()[s].queryHull, hullRanges_[s]);
  }
  vertices_ = gl::Buffer(vertices.size() * sizeof(TreeVertex), vertices.data(), 0);
  indices_ = gl::Buffer(indices.size() * sizeof(std::uint32_t), indices.data(), 0);
  // A segment holds every tree (the largest draw), so the ring never grows.
  instances_ = std::make_unique<gl::StreamRing>(std::max<size_t>(1, forest.trees().size()) * sizeof(InstanceGpu), sizeof(InstanceGpu));
  groupOf_.reserve(forest.trees().size());

  const GLuint vao = vertexArray_.id();
  glVertexArrayVertexBuffer(vao, 0, vertices_.id(), 0, sizeof(TreeVertex));
  glVertexArrayElementBuffer(vao, indices_.id());
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, a * sizeof(glm::vec3));
    glVertexArrayAttribBinding(vao, a, 0);
  }
  glVertexArrayVertexBuffer(vao, 1, instances_->id(), 0, sizeof(InstanceGpu));
  glVertexArrayBindingDivisor(vao, 1, 1);
  for (GLuint a = 3; a < 6; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, 4, GL_FLOAT, GL_FALSE, (a - 3) * sizeof(glm::vec4));
    glVertexArrayAttribBinding(vao, a, 1);
  }
  glEnableVertexArrayAttrib(vao, 6);
  glVertexArrayAttribIFormat(vao, 6, 1, GL_UNSIGNED_INT, offsetof(InstanceGpu, objectId));
  glVertexArrayAttribBinding(vao, 6, 1);
}

std::vector<std::uint32_t> TreeRenderer::treesInFrustum(const Camera& camera) const {
  const Frustum frustum(camera);
  std::vector<std::uint32_t> trees;
  for (std::uint32_t t = 0; t < forest_.trees().size(); ++t)
    if (frustum.mayIntersect(forest_.treeBounds(t))) trees.push_back(t);
  return trees;
}

TreeRenderer::Stats TreeRenderer::draw(const Camera& camera, std::span<const std::uint32_t> trees, double time,
                                       const SunSettings& sun) const {
  return draw(DrawView::fromCamera(camera, time, sun), trees);
}

TreeRenderer::Stats TreeRenderer::draw(const DrawView& view, std::span<const std::uint32_t> trees) const {
  if (filter_) {
    const Groups groups = writeInstances(view, trees, {});
    return groups.empty ? Stats{} : drawFiltered(view, groups);
  }
  return drawInstances(view, trees, {}, program_);
}

TreeRenderer::Stats TreeRenderer::drawQueries(const DrawView& view, std::span<const std::uint32_t> trees,
                                              std::span<const std::uint32_t> slots, bool hulls) const {
  if (!queryProgram_) queryProgram_ = loadSurfaceProgram("trees.vert", "trees.frag", SurfaceOutput::QueryStamp);
  return drawInstances(view, trees, slots, *queryProgram_, hulls);
}

TreeRenderer::Groups TreeRenderer::writeInstances(const DrawView& view, std::span<const std::uint32_t> trees,
                                                  std::span<const std::uint32_t> ids) const {
  Groups groups;
  const double time = view.time;
  // Instances grouped by (species, LOD), base positions relative to the eye in double, written
  // straight into the ring: count the groups, then place each tree in its group's part.
  std::array<int, kGroups> cursor{};
  groupOf_.clear();
  for (std::uint32_t t : trees) {
    const int group = static_cast<int>(forest_.trees()[t].species) * kTreeLods + forest_.lodFor(t, view.lodEye);
    groupOf_.push_back(static_cast<std::uint8_t>(group));
    ++groups.counts[static_cast<size_t>(group)];
  }
  if (groupOf_.empty()) return groups;
  groups.empty = false;
  for (size_t g = 1; g < cursor.size(); ++g) cursor[g] = cursor[g - 1] + groups.counts[g - 1];
  groups.first = cursor;
  const GLuint ringBefore = instances_->id();
  const gl::StreamRing::Allocation part = instances_->allocate(groupOf_.size() * sizeof(InstanceGpu));
  if (instances_->id() != ringBefore) glVertexArrayVertexBuffer(vertexArray_.id(), 1, instances_->id(), 0, sizeof(InstanceGpu));
  auto* out = static_cast<InstanceGpu*>(part.data);
  size_t k = 0;  // the tree's place in `trees` (and `ids`)
  const bool windy = forest_.settings().wind_strength != 0.0;
  for (std::uint32_t t : trees) {
    const vegetation::TreeInstance& tree = forest_.trees()[t];
    const size_t i = k++;
    InstanceGpu& g = out[cursor[groupOf_[i]]++];
    // Forest::treeTransform's factors: translate · windShear · rotateY(yaw) · scale.
    const glm::dvec2 shear = windy ? vegetation::windShear(forest_.settings(), tree.swayPhase, time) : glm::dvec2(0.0);
    g.baseScale = glm::vec4(glm::vec3(tree.position - view.origin), static_cast<float>(tree.scale));
    g.rotationShear = glm::vec4(static_cast<float>(std::cos(tree.yaw)), static_cast<float>(std::sin(tree.yaw)),
                                static_cast<float>(shear.x), static_cast<float>(shear.y));
    g.tint = glm::vec4(tree.tint, 1.0f);
    g.objectId = ids.empty() ? objectIdBase_ + t : ids[i];
    g.padding[0] = g.padding[1] = g.padding[2] = 0;
  }
  groups.baseInstance = static_cast<GLuint>(part.offset / sizeof(InstanceGpu));
  return groups;
}

TreeRenderer::Stats TreeRenderer::drawFiltered(const DrawView& view, const Groups& groups) const {
  Stats stats;
  std::array<GpuCasterFilter::Group, kGroups> list{};
  size_t listed = 0;
  for (int s = 0; s < kSpeciesCount; ++s)
    for (int lod = 0; lod < kTreeLods; ++lod) {
      const size_t g = static_cast<size_t>(s * kTreeLods + lod);
      if (groups.counts[g] == 0) continue;
      const Range& r = ranges_[s][lod];
      list[listed++] = {static_cast<std::uint32_t>(groups.first[g]), static_cast<std::uint32_t>(groups.counts[g]), s,
                        static_cast<std::uint32_t>(r.indexCount), static_cast<std::uint32_t>(r.firstIndex), r.baseVertex};
      stats.trees += groups.counts[g];
      stats.treesPerLod[lod] += groups.counts[g];  // given; the triangles drawn are the GPU's to count
    }
  const std::span<const GpuCasterFilter::Group> given(list.data(), listed);
  viewUniforms_.bind(viewBlock(view));
  auto drawKept = [&](std::size_t commands) {  // one indirect draw per group, of what the filter kept
    program_.use();
    glBindVertexArray(vertexArray_.id());
    glVertexArrayVertexBuffer(vertexArray_.id(), 1, filter_->output(), 0, sizeof(InstanceGpu));
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, filter_->commands());
    for (size_t g = 0; g < listed; ++g) {
      glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(static_cast<std::uintptr_t>(commands + g * GpuCasterFilter::commandBytes())));
      ++stats.draws;
    }
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glVertexArrayVertexBuffer(vertexArray_.id(), 1, instances_->id(), 0, sizeof(InstanceGpu));
    glBindVertexArray(0);
  };
  if (!filter_->occlusion()) {
    drawKept(filter_->select(instances_->id(), groups.baseInstance, given));
    return stats;
  }
  // The trees that counted in the last frame first; the others against what they and the terrain drew.
  drawKept(filter_->select(instances_->id(), groups.baseInstance, given, GpuCasterFilter::Phase::Counted));
  filter_->buildOccluders();
  drawKept(filter_->select(instances_->id(), groups.baseInstance, given, GpuCasterFilter::Phase::Others));
  return stats;
}

TreeRenderer::Stats TreeRenderer::drawInstances(const DrawView& view, std::span<const std::uint32_t> trees,
                                                std::span<const std::uint32_t> ids, const gl::Program& program, bool hulls) const {
  Stats stats;
  const Groups groups = writeInstances(view, trees, ids);
  if (groups.empty) return stats;
  const std::array<int, kGroups>& counts = groups.counts;
  const std::array<int, kGroups>& first = groups.first;
  const GLuint baseInstance = groups.baseInstance;

  viewUniforms_.bind(viewBlock(view));
  program.use();
  glBindVertexArray(vertexArray_.id());
  for (int s = 0; s < kSpeciesCount; ++s) {
    for (int lod = 0; lod < kTreeLods; ++lod) {
      const int count = counts[static_cast<size_t>(s * kTreeLods + lod)];
      if (count == 0) continue;
      const Range& r = hulls && hullRanges_[s].indexCount > 0 ? hullRanges_[s] : ranges_[s][lod];
      glDrawElementsInstancedBaseVertexBaseInstance(
          GL_TRIANGLES, r.indexCount, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(r.firstIndex) * sizeof(std::uint32_t)), count,
          r.baseVertex, baseInstance + static_cast<GLuint>(first[static_cast<size_t>(s * kTreeLods + lod)]));
      stats.trees += count;
      stats.treesPerLod[lod] += count;
      stats.triangles += static_cast<long long>(count) * r.indexCount / 3;
      ++stats.draws;
    }
  }
  glBindVertexArray(0);
  return stats;
}

}  // namespace forest::render
