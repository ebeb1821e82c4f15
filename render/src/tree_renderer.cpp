#include "forest/render/tree_renderer.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "forest/core/frustum.hpp"
#include "forest/gl/shader.hpp"
#include "forest/render/impostor_atlas.hpp"
#include "gpu_caster_filter.hpp"

namespace forest::render {
namespace {

using vegetation::kSpeciesCount;
using vegetation::kTreeLods;

struct TreeVertex {
  glm::vec3 position, normal, albedo;
};

}  // namespace

double impostorShare(const ImpostorSwitch& impostors, double eyeDistance) {
  if (!(impostors.distance > 0.0)) return 0.0;
  if (!(impostors.band > 0.0)) return eyeDistance >= impostors.distance ? 1.0 : 0.0;
  return std::clamp((eyeDistance - impostors.distance) / (impostors.band * impostors.distance), 0.0, 1.0);
}

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
  vegetation::TreeMesh quad;
  quad.positions = {{-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}, {-1.0f, 1.0f, 0.0f}};
  quad.normals = quad.albedo = std::vector<glm::vec3>(4, glm::vec3(0.0f));
  quad.indices = {0, 1, 2, 0, 2, 3};
  append(quad, quadRange_);
  vertices_ = gl::Buffer(vertices.size() * sizeof(TreeVertex), vertices.data(), 0);
  indices_ = gl::Buffer(indices.size() * sizeof(std::uint32_t), indices.data(), 0);
  // A segment holds every tree (the largest draw without impostors); a cross-fade's second
  // instances may grow the ring once.
  instances_ = std::make_unique<gl::StreamRing>(std::max<size_t>(1, forest.trees().size()) * sizeof(InstanceGpu), sizeof(InstanceGpu));
  groupOf_.reserve(forest.trees().size());
  fadeOf_.reserve(forest.trees().size());

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
  glEnableVertexArrayAttrib(vao, 7);
  glVertexArrayAttribIFormat(vao, 7, 2, GL_UNSIGNED_INT, offsetof(InstanceGpu, fadeBits));
  glVertexArrayAttribBinding(vao, 7, 1);
}

void TreeRenderer::setImpostors(const ImpostorAtlas* atlas, const ImpostorSwitch& impostors) {
  atlas_ = atlas;
  impostors_ = atlas ? impostors : ImpostorSwitch{};
}

const gl::Program& TreeRenderer::programFor(int representation, bool query) const {
  const SurfaceOutput output = query ? SurfaceOutput::QueryStamp : output_;
  auto load = [&](std::optional<gl::Program>& program, const char* vertex, const char* fragment, const std::string& defines) -> const gl::Program& {
    if (!program) program = loadSurfaceProgram(vertex, fragment, output, defines);
    return *program;
  };
  if (representation < kTreeLods) return query ? load(queryProgram_, "trees.vert", "trees.frag", "") : program_;
  if (representation < kImpostor)
    return load(query ? fadingQueryProgram_ : fadingProgram_, "trees.vert", "trees.frag+cross_fade.glsl", "#define CROSS_FADE 1\n");
  return load(query ? impostorQueryProgram_ : impostorProgram_, "impostor.vert", "impostor.frag+crown_slab.glsl+cross_fade.glsl",
              gl::readShader("impostor.glsl"));
}

const TreeRenderer::Range& TreeRenderer::rangeFor(int species, int representation, bool hull) const {
  if (representation == kImpostor) return quadRange_;
  if (hull && hullRanges_[species].indexCount > 0) return hullRanges_[species];
  return ranges_[species][representation % kTreeLods];
}

void TreeRenderer::beginImpostors() const {
  atlas_->bind();
  cullingWasOn_ = glIsEnabled(GL_CULL_FACE) == GL_TRUE;
  glDisable(GL_CULL_FACE);
}

void TreeRenderer::endImpostors() const {
  if (cullingWasOn_) glEnable(GL_CULL_FACE);
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
    return groups.empty ? Stats{} : drawFiltered(view, groups, trees.size());
  }
  return drawInstances(view, trees, {}, false);
}

TreeRenderer::Stats TreeRenderer::drawQueries(const DrawView& view, std::span<const std::uint32_t> trees,
                                              std::span<const std::uint32_t> slots, bool hulls) const {
  return drawInstances(view, trees, slots, true, hulls);
}

TreeRenderer::Groups TreeRenderer::writeInstances(const DrawView& view, std::span<const std::uint32_t> trees,
                                                  std::span<const std::uint32_t> ids) const {
  Groups groups;
  const double time = view.time;
  // Instances grouped by (species, representation), base positions relative to the eye in double,
  // written straight into the ring: count the groups, then place each tree in its groups' parts.
  std::array<int, kGroups> cursor{};
  groupOf_.clear();
  fadeOf_.clear();
  const bool impostors = atlas_ && impostors_.distance > 0.0;
  size_t instances = 0;
  for (std::uint32_t t : trees) {
    const int species = static_cast<int>(forest_.trees()[t].species);
    const double share = impostors ? impostorShare(impostors_, forest_.lodDistance(t, view.lodEye)) : 0.0;
    const int lod = share < 1.0 ? forest_.lodFor(t, view.lodEye) : 0;
    const int representation = share >= 1.0 ? kImpostor : share > 0.0 ? kTreeLods + lod : lod;
    const int group = species * kRepresentations + representation;
    groupOf_.push_back(static_cast<std::uint8_t>(group));
    fadeOf_.push_back(static_cast<float>(share));
    ++groups.counts[static_cast<size_t>(group)];
    ++instances;
    if (representation != kImpostor && share > 0.0) {  // cross-fading: its impostor too
      ++groups.counts[static_cast<size_t>(species * kRepresentations + kImpostor)];
      ++instances;
    }
  }
  if (groupOf_.empty()) return groups;
  groups.empty = false;
  for (size_t g = 1; g < cursor.size(); ++g) cursor[g] = cursor[g - 1] + groups.counts[g - 1];
  groups.first = cursor;
  const GLuint ringBefore = instances_->id();
  const gl::StreamRing::Allocation part = instances_->allocate(instances * sizeof(InstanceGpu));
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
    g.fadeBits = std::bit_cast<std::uint32_t>(fadeOf_[i]);
    g.species = static_cast<std::uint32_t>(tree.species);
    g.padding = 0;
    const int impostorGroup = static_cast<int>(tree.species) * kRepresentations + kImpostor;
    if (groupOf_[i] != impostorGroup && fadeOf_[i] > 0.0f) out[cursor[static_cast<size_t>(impostorGroup)]++] = g;
  }
  groups.baseInstance = static_cast<GLuint>(part.offset / sizeof(InstanceGpu));
  return groups;
}

TreeRenderer::Stats TreeRenderer::drawFiltered(const DrawView& view, const Groups& groups, std::size_t trees) const {
  Stats stats;
  stats.trees = static_cast<int>(trees);
  std::array<GpuCasterFilter::Group, kGroups> list{};
  std::array<int, kGroups> representationOf{};
  size_t listed = 0;
  for (int s = 0; s < kSpeciesCount; ++s)
    for (int rep = 0; rep < kRepresentations; ++rep) {
      const size_t g = static_cast<size_t>(s * kRepresentations + rep);
      if (groups.counts[g] == 0) continue;
      const Range& r = rangeFor(s, rep, false);
      representationOf[listed] = rep;
      list[listed++] = {static_cast<std::uint32_t>(groups.first[g]), static_cast<std::uint32_t>(groups.counts[g]), s,
                        static_cast<std::uint32_t>(r.indexCount), static_cast<std::uint32_t>(r.firstIndex), r.baseVertex};
      // Given; the triangles drawn are the GPU's to count.
      if (rep == kImpostor) stats.impostors += groups.counts[g];
      else stats.treesPerLod[rep % kTreeLods] += groups.counts[g];
    }
  const std::span<const GpuCasterFilter::Group> given(list.data(), listed);
  viewUniforms_.bind(viewBlock(view));
  auto drawKept = [&](std::size_t commands) {  // one indirect draw per group, of what the filter kept
    glBindVertexArray(vertexArray_.id());
    glVertexArrayVertexBuffer(vertexArray_.id(), 1, filter_->output(), 0, sizeof(InstanceGpu));
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, filter_->commands());
    for (size_t g = 0; g < listed; ++g) {
      const bool impostor = representationOf[g] == kImpostor;
      programFor(representationOf[g], false).use();
      if (impostor) beginImpostors();
      glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(static_cast<std::uintptr_t>(commands + g * GpuCasterFilter::commandBytes())));
      if (impostor) endImpostors();
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
                                                std::span<const std::uint32_t> ids, bool query, bool hulls) const {
  Stats stats;
  const Groups groups = writeInstances(view, trees, ids);
  if (groups.empty) return stats;
  stats.trees = static_cast<int>(trees.size());
  viewUniforms_.bind(viewBlock(view));
  glBindVertexArray(vertexArray_.id());
  for (int s = 0; s < kSpeciesCount; ++s) {
    for (int rep = 0; rep < kRepresentations; ++rep) {
      const size_t g = static_cast<size_t>(s * kRepresentations + rep);
      const int count = groups.counts[g];
      if (count == 0) continue;
      const Range& r = rangeFor(s, rep, hulls);
      const bool impostor = rep == kImpostor;
      programFor(rep, query).use();
      if (impostor) beginImpostors();
      glDrawElementsInstancedBaseVertexBaseInstance(
          GL_TRIANGLES, r.indexCount, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::uintptr_t>(r.firstIndex) * sizeof(std::uint32_t)), count,
          r.baseVertex, groups.baseInstance + static_cast<GLuint>(groups.first[g]));
      if (impostor) endImpostors();
      if (impostor) stats.impostors += count;
      else stats.treesPerLod[rep % kTreeLods] += count;
      stats.triangles += static_cast<long long>(count) * r.indexCount / 3;
      ++stats.draws;
    }
  }
  glBindVertexArray(0);
  return stats;
}

}  // namespace forest::render
