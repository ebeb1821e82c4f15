#include "gpu_caster_filter.hpp"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "forest/core/error.hpp"
#include "shadow_pass.hpp"

namespace forest::render {
namespace {

// Texture units, as the shaders bind them.
constexpr GLuint kMaskUnit = 5;       // receiver_mask.comp's uSurface, the others' uMask
constexpr GLuint kOccludersUnit = 6;  // caster_filter.comp's uOccluders
constexpr GLuint kMapUnit = 7;        // occluder_depths.comp's and caster_contribution.comp's uMap
constexpr GLuint kReadsUnit = 8;      // caster_filter.comp's uReads, caster_contribution.comp's uIds
// The map depth that the GPU's float32 placement of a receiver or a caster corner may miss by
// (as shadows::ReceiverMask's kDepthTolerance).
constexpr float kDepthTolerance = 1e-5f;
constexpr int kSlabs = vegetation::kCasterSlabs, kMaxSpecies = 4;
static_assert(vegetation::kSpeciesCount <= kMaxSpecies && vegetation::kCasterSlabs == 8,
              "caster_filter.comp's Params holds 4 species of 8 slabs");

int levelsFor(int size) { return static_cast<int>(std::floor(std::log2(static_cast<double>(size)))) + 1; }

}  // namespace

struct GpuCasterFilter::Params {  // std430, caster_filter.comp
  glm::vec4 slabs[kMaxSpecies * kSlabs];
  glm::uvec4 groups[kMaxGroups];  // first, count, species, command
  std::uint32_t groupCount, instanceBase, instanceCount, commandBase;
};

GpuCasterFilter::GpuCasterFilter(const vegetation::Forest& forest, std::uint32_t treeIdBase)
    : forest_(forest),
      treeIdBase_(treeIdBase),
      build_(gl::loadProgram({"receiver_mask.comp"})),
      reduce_(gl::loadProgram({"receiver_mask_reduce.comp"})),
      reach_program_(gl::loadProgram({"receiver_reach.comp"})),
      filter_(gl::loadProgram({"caster_filter.comp+crown_slab.glsl"})),
      occludersFromMap_(gl::loadProgram({"occluder_depths.comp"}, "#define FROM_MAP 1\n")),
      occludersReduce_(gl::loadProgram({"occluder_depths.comp"})),
      markCounted_(gl::loadProgram({"caster_contribution.comp"})),
      counted_(std::max<std::size_t>(1, forest.trees().size()) * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT),
      flags_(2 * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT),
      params_(sizeof(Params), nullptr, GL_DYNAMIC_STORAGE_BIT),
      commands_(static_cast<std::size_t>(kMaxDraws) * kMaxGroups * sizeof(Command), nullptr, GL_DYNAMIC_STORAGE_BIT) {
  for (int s = 0; s < vegetation::kSpeciesCount; ++s)
    for (int k = 0; k < kSlabs; ++k) {
      const vegetation::CrownSlab& slab = forest.casterSlabs(static_cast<vegetation::Species>(s))[static_cast<size_t>(k)];
      // An empty slab (no triangle reaches into it) as (1, 0): heights the shader skips.
      slabs_[static_cast<size_t>(s * kSlabs + k)] =
          slab.empty() ? glm::vec4(1.0f, 0.0f, 0.0f, 0.0f) : glm::vec4(glm::dvec4(slab.bottom, slab.top, slab.radiusBottom, slab.radiusTop));
    }
}

void GpuCasterFilter::beginFrame(bool occlusion) {
  if (frame_ == 0) {
    const GLuint zero = 0;
    glClearNamedBufferData(counted_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
  lastFrame_ = marked_ ? frame_ : 0;
  ++frame_;
  marked_ = false;
  occlusion_ = occlusion;
  outputUsed_ = 0;
  draws_ = 0;
  for (std::vector<int>& d : sliceDraws_) d.clear();
}

void GpuCasterFilter::ensureMask(int mapSize) {
  if (mapSize == mapSize_) return;
  levels_ = levelsFor(mapSize);
  mask_ = gl::Texture(GL_R32UI, mapSize, mapSize, levels_);
  reads_ = gl::Texture(GL_R32UI, mapSize, mapSize);
  readsAlongX_ = gl::Texture(GL_R32UI, mapSize, mapSize);
  for (GLuint id : {reads_.id(), readsAlongX_.id()}) {
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  occluders_ = gl::Texture(GL_R32F, mapSize, mapSize, levels_);
  glTextureParameteri(occluders_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
  glTextureParameteri(occluders_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  // An integer texture is complete only with nearest filtering (texelFetch reads it, by level).
  glTextureParameteri(mask_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
  glTextureParameteri(mask_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  mapSize_ = mapSize;
}

void GpuCasterFilter::buildMask(int slice, const gl::Texture& surface, const Camera& camera, double zMin, double zMax,
                                const shadows::ShadowSetup& setup, const glm::dvec3& eye, const gl::Texture& map, const gl::Texture* ids,
                                double reachTexels) {
  if (slice < 0 || slice >= kMaxSlices) throw Error(fmt::format("GpuCasterFilter: slice {} outside 0…{}", slice, kMaxSlices - 1));
  const int mapSize = map.width();
  ensureMask(mapSize);
  slice_ = slice;
  map_ = &map;
  ids_ = ids;
  const glm::dmat4 toClip = eyeRelativeToShadowClip(setup, eye);
  toClip_ = glm::mat4(toClip);
  fromClip_ = glm::mat4(glm::inverse(toClip));  // in double: the light's lines through texel centres
  linearDepth_ = setup.linearDepth;
  // (p − origin, 1) → z_L for a view origin, as ShadowPass::drawSlice forms it.
  const glm::dvec4& row = setup.worldToLightDepth;
  auto lightDepthRowFrom = [&](const glm::dvec3& origin) {
    return glm::vec4(glm::dvec4(glm::dvec3(row), row.w + glm::dot(glm::dvec3(row), origin)));
  };
  lightDepthRow_ = lightDepthRowFrom(eye);
  reach_ = static_cast<float>(reachTexels);
  const GLuint zero = 0;
  glClearTexImage(mask_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glClearNamedBufferData(flags_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  // The pixel rays as ReceiverPixels::read forms them, from the camera at `eye`.
  const double tanY = std::tan(0.5 * camera.fovy), tanX = tanY * camera.aspect;
  build_.set("uToClip", glm::mat4(toClip * glm::translate(glm::dmat4(1.0), camera.position - eye)));
  build_.set("uLightDepthRow", lightDepthRowFrom(camera.position));
  build_.set("uLinearDepth", linearDepth_ ? 1 : 0);
  build_.set("uForward", glm::vec3(camera.forward()));
  build_.set("uRight", glm::vec3(camera.right()));
  build_.set("uUp", glm::vec3(camera.up()));
  build_.set("uTanHalf", glm::vec2(tanX, tanY));
  build_.set("uDepthRange", glm::vec2(static_cast<float>(zMin), static_cast<float>(zMax)));
  build_.set("uMapSize", mapSize);
  build_.use();
  glBindTextureUnit(kMaskUnit, surface.id());
  glBindImageTexture(0, mask_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, flags_.id());
  glDispatchCompute(static_cast<GLuint>((surface.width() + 7) / 8), static_cast<GLuint>((surface.height() + 7) / 8), 1);
  reduce_.use();
  for (int level = 1; level < levels_; ++level) {
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindImageTexture(0, mask_.id(), level - 1, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glBindImageTexture(1, mask_.id(), level, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32UI);
    const int size = std::max(1, mapSize >> level);
    glDispatchCompute(static_cast<GLuint>((size + 7) / 8), static_cast<GLuint>((size + 7) / 8), 1);
  }
  // What the lookups read: the mask's level 0 spread by the reach, along x then y.
  reach_program_.use();
  reach_program_.set("uRadius", static_cast<int>(std::ceil(reachTexels)));
  const GLuint groups = static_cast<GLuint>((mapSize + 7) / 8);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  reach_program_.set("uAxis", glm::ivec2(1, 0));
  glBindImageTexture(0, mask_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
  glBindImageTexture(1, readsAlongX_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32UI);
  glDispatchCompute(groups, groups, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  reach_program_.set("uAxis", glm::ivec2(0, 1));
  glBindImageTexture(0, readsAlongX_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
  glBindImageTexture(1, reads_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32UI);
  glDispatchCompute(groups, groups, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
  glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
  glBindTextureUnit(kMaskUnit, 0);
}

void GpuCasterFilter::ensureOutput(std::size_t instances) {
  const std::size_t stride = sizeof(glm::vec4) * 4;  // TreeRenderer::InstanceGpu
  if (output_.size() >= (outputUsed_ + instances) * stride) return;
  // A new buffer: draws already issued keep the old one alive until they finish (GL defers deletion).
  output_ = gl::Buffer(std::max<std::size_t>(2 * output_.size(), (outputUsed_ + instances) * stride), nullptr, 0);
  outputUsed_ = 0;
}

std::size_t GpuCasterFilter::select(GLuint instances, std::uint32_t baseInstance, std::span<const Group> groups, Phase phase) {
  if (groups.size() > static_cast<std::size_t>(kMaxGroups)) throw Error("GpuCasterFilter: more than " + std::to_string(kMaxGroups) + " groups in a draw");
  if (draws_ >= kMaxDraws) throw Error(fmt::format("GpuCasterFilter: more than {} tree draws in a frame", kMaxDraws));
  std::uint32_t total = 0;
  for (const Group& g : groups) total = std::max(total, g.first + g.count);
  ensureOutput(total);
  Params params{};
  std::copy(slabs_.begin(), slabs_.end(), params.slabs);
  std::array<Command, kMaxGroups> commands{};
  for (std::size_t g = 0; g < groups.size(); ++g) {
    params.groups[g] = glm::uvec4(groups[g].first, groups[g].count, static_cast<std::uint32_t>(groups[g].species), static_cast<std::uint32_t>(g));
    commands[g] = {groups[g].indexCount, 0, groups[g].firstIndex, groups[g].baseVertex, outputUsed_ + groups[g].first};
  }
  params.groupCount = static_cast<std::uint32_t>(groups.size());
  params.instanceBase = baseInstance;
  params.instanceCount = total;
  params.commandBase = static_cast<std::uint32_t>(draws_ * kMaxGroups);
  params_.upload(0, sizeof params, &params);
  const std::size_t commandBase = static_cast<std::size_t>(draws_) * kMaxGroups * sizeof(Command);
  commands_.upload(commandBase, commands.size() * sizeof(Command), commands.data());
  sliceDraws_[static_cast<size_t>(slice_)].push_back(draws_++);
  outputUsed_ += total;

  // The slice's selection: room for every tree once (a tree is drawn at most once into a slice),
  // its count zeroed at the slice's first draw.
  gl::Buffer& selection = selection_[static_cast<size_t>(slice_)];
  const std::size_t capacity = forest_.trees().size();
  if (selection.id() == 0) selection = gl::Buffer((1 + capacity) * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
  if (sliceDraws_[static_cast<size_t>(slice_)].size() == 1) {
    const GLuint zero = 0;
    glClearNamedBufferSubData(selection.id(), GL_R32UI, 0, sizeof zero, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }

  setCommonUniforms(filter_);
  filter_.set("uToClip", toClip_);
  filter_.set("uFromClip", fromClip_);
  filter_.set("uLightDepthRow", lightDepthRow_);
  filter_.set("uLinearDepth", linearDepth_ ? 1 : 0);
  filter_.set("uSelectionCapacity", static_cast<std::uint32_t>(capacity));
  filter_.set("uPhase", static_cast<int>(phase));
  filter_.set("uLastFrame", lastFrame_);
  filter_.use();
  glBindTextureUnit(kOccludersUnit, occluders_.id());
  glBindTextureUnit(kReadsUnit, reads_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, counted_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, instances);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, output_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, commands_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, selection.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, flags_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, params_.id());
  glBindTextureUnit(kMaskUnit, mask_.id());
  glDispatchCompute((total + 63) / 64, 1, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  glBindTextureUnit(kMaskUnit, 0);
  glBindTextureUnit(kOccludersUnit, 0);
  glBindTextureUnit(kReadsUnit, 0);
  return commandBase;
}

void GpuCasterFilter::setCommonUniforms(const gl::Program& program) const {
  program.set("uMapSize", mapSize_);
  program.set("uLevels", levels_);
  program.set("uReach", reach_);
  program.set("uDepthTolerance", kDepthTolerance);
  program.set("uTreeIdBase", treeIdBase_);
  program.set("uTreeCount", static_cast<std::uint32_t>(forest_.trees().size()));
}

namespace {
// The map's layers read as depths (texelFetch) while `reading` lives: its comparison off, then on again.
struct MapDepthsReadable {
  explicit MapDepthsReadable(const gl::Texture& map) : id(map.id()) {
    glTextureParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glBindTextureUnit(kMapUnit, id);
  }
  ~MapDepthsReadable() {
    glBindTextureUnit(kMapUnit, 0);
    glTextureParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  }
  MapDepthsReadable(const MapDepthsReadable&) = delete;
  MapDepthsReadable& operator=(const MapDepthsReadable&) = delete;
  GLuint id;
};
}  // namespace

void GpuCasterFilter::buildOccluders() {
  if (!occlusion()) throw Error("GpuCasterFilter::buildOccluders: no occlusion this frame");
  const MapDepthsReadable readable(*map_);
  occludersFromMap_.set("uLayer", slice_);
  occludersFromMap_.use();
  int size = occluders_.width();
  glBindImageTexture(1, occluders_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glDispatchCompute(static_cast<GLuint>((size + 7) / 8), static_cast<GLuint>((size + 7) / 8), 1);
  occludersReduce_.use();
  for (int level = 1; level < levels_; ++level) {
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glBindImageTexture(0, occluders_.id(), level - 1, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindImageTexture(1, occluders_.id(), level, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    size = std::max(1, occluders_.width() >> level);
    glDispatchCompute(static_cast<GLuint>((size + 7) / 8), static_cast<GLuint>((size + 7) / 8), 1);
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
}

void GpuCasterFilter::markCounted() {
  if (!occlusion()) return;
  const MapDepthsReadable readable(*map_);
  setCommonUniforms(markCounted_);
  markCounted_.set("uLayer", slice_);
  markCounted_.set("uFrame", frame_);
  markCounted_.use();
  glBindTextureUnit(kMaskUnit, mask_.id());
  glBindTextureUnit(kReadsUnit, ids_->id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, counted_.id());
  glDispatchCompute(static_cast<GLuint>((mapSize_ + 7) / 8), static_cast<GLuint>((mapSize_ + 7) / 8), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glBindTextureUnit(kMaskUnit, 0);
  glBindTextureUnit(kReadsUnit, 0);
  marked_ = true;
}

std::uint32_t GpuCasterFilter::selectedCount(int slice) const {
  std::uint32_t count = 0;
  if (slice < 0 || slice >= kMaxSlices || sliceDraws_[static_cast<size_t>(slice)].empty()) return 0;
  if (selection_[static_cast<size_t>(slice)].id() == 0) return 0;
  glGetNamedBufferSubData(selection_[static_cast<size_t>(slice)].id(), 0, sizeof count, &count);
  return count;
}

std::vector<std::uint32_t> GpuCasterFilter::selectedIds(int slice) const {
  if (slice < 0 || slice >= kMaxSlices || sliceDraws_[static_cast<size_t>(slice)].empty()) return {};
  std::vector<std::uint32_t> ids(std::min<std::size_t>(selectedCount(slice), forest_.trees().size()));
  if (!ids.empty())
    glGetNamedBufferSubData(selection_[static_cast<size_t>(slice)].id(), sizeof(std::uint32_t),
                            static_cast<GLsizeiptr>(ids.size() * sizeof(std::uint32_t)), ids.data());
  return ids;
}

long long GpuCasterFilter::selectedTriangles(int slice) const {
  long long triangles = 0;
  if (slice < 0 || slice >= kMaxSlices) return 0;
  std::array<Command, kMaxGroups> commands{};
  for (int draw : sliceDraws_[static_cast<size_t>(slice)]) {
    glGetNamedBufferSubData(commands_.id(), static_cast<GLintptr>(draw) * kMaxGroups * sizeof(Command),
                            static_cast<GLsizeiptr>(commands.size() * sizeof(Command)), commands.data());
    for (const Command& c : commands) triangles += static_cast<long long>(c.instanceCount) * (c.count / 3);
  }
  return triangles;
}

}  // namespace forest::render
