#include "forest/gl/objects.hpp"

#include <fmt/format.h>

#include <atomic>

#include "forest/core/error.hpp"

namespace forest::gl {
namespace {

std::atomic<std::int64_t> gBytes{0};
std::atomic<std::int64_t> gPeak{0};

void account(std::int64_t delta) {
  const std::int64_t now = gBytes.fetch_add(delta) + delta;
  std::int64_t peak = gPeak.load();
  while (now > peak && !gPeak.compare_exchange_weak(peak, now)) {
  }
}

}  // namespace

GpuMemory gpuMemory() { return {gBytes.load(), gPeak.load()}; }

void BufferDeleter::operator()(GLuint id) const { glDeleteBuffers(1, &id); }
void TextureDeleter::operator()(GLuint id) const { glDeleteTextures(1, &id); }
void FramebufferDeleter::operator()(GLuint id) const { glDeleteFramebuffers(1, &id); }
void VertexArrayDeleter::operator()(GLuint id) const { glDeleteVertexArrays(1, &id); }
void QueryDeleter::operator()(GLuint id) const { glDeleteQueries(1, &id); }
void ProgramDeleter::operator()(GLuint id) const { glDeleteProgram(id); }

Buffer::Buffer(std::size_t bytes, const void* data, GLbitfield flags) {
  if (bytes == 0) throw Error("gl::Buffer: zero-sized buffer");
  GLuint id = 0;
  glCreateBuffers(1, &id);
  name_ = UniqueName<BufferDeleter>(id);
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(bytes), data, flags);
  checkError("glNamedBufferStorage");
  bytes_ = bytes;
  account(static_cast<std::int64_t>(bytes));
}

void Buffer::release() {
  if (name_) account(-static_cast<std::int64_t>(bytes_));
  name_.reset();
  bytes_ = 0;
}

Buffer::~Buffer() { release(); }

ReadMappedStamps::ReadMappedStamps(std::size_t count) {
  const GLbitfield access = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  buffer_ = Buffer(count * sizeof(std::uint32_t), nullptr, access | GL_DYNAMIC_STORAGE_BIT);
  const GLuint zero = 0;  // no frame's stamp
  glClearNamedBufferData(buffer_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  stamps_ = static_cast<const std::uint32_t*>(
      glMapNamedBufferRange(buffer_.id(), 0, static_cast<GLsizeiptr>(count * sizeof(std::uint32_t)), access));
  if (!stamps_) throw Error(fmt::format("gl::ReadMappedStamps: cannot map a buffer of {} stamps", count));
  count_ = count;
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    name_ = std::move(other.name_);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

void Buffer::upload(std::size_t offset, std::size_t bytes, const void* data) {
  if (offset + bytes > bytes_) {
    throw Error(fmt::format("gl::Buffer::upload: {} bytes at {} exceed the buffer's {}", bytes, offset, bytes_));
  }
  glNamedBufferSubData(id(), static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
}

std::size_t bytesPerTexel(GLenum internalFormat) {
  switch (internalFormat) {
    case GL_R8: return 1;
    case GL_RG8: case GL_R16F: case GL_DEPTH_COMPONENT16: return 2;
    case GL_RGBA8: case GL_SRGB8_ALPHA8: case GL_RGB10_A2: case GL_R32F: case GL_R32UI: case GL_R32I:
    case GL_RG16F: case GL_RG16_SNORM: case GL_R11F_G11F_B10F: case GL_DEPTH_COMPONENT24: case GL_DEPTH_COMPONENT32F:
    case GL_DEPTH24_STENCIL8: return 4;
    case GL_RGBA16F: case GL_RG32F: case GL_RG32UI: case GL_DEPTH32F_STENCIL8: return 8;
    case GL_RGBA32F: case GL_RGBA32UI: return 16;
    default: throw Error(fmt::format("gl::Texture: internal format 0x{:04x} has no size entry", internalFormat));
  }
}

Texture::Texture(GLenum internalFormat, int width, int height, int levels, int layers) {
  GLint maxSize = 0, maxLayers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (width <= 0 || height <= 0 || width > maxSize || height > maxSize || levels <= 0 || layers < 0 || layers > maxLayers) {
    throw Error(fmt::format("gl::Texture: size {}x{} ({} levels, {} layers) outside 1..{} ({} layers)", width, height, levels,
                            layers, maxSize, maxLayers));
  }
  const std::size_t texel = bytesPerTexel(internalFormat);
  GLuint id = 0;
  glCreateTextures(layers > 0 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D, 1, &id);
  name_ = UniqueName<TextureDeleter>(id);
  if (layers > 0) {
    glTextureStorage3D(id, levels, internalFormat, width, height, layers);
    checkError("glTextureStorage3D");
  } else {
    glTextureStorage2D(id, levels, internalFormat, width, height);
    checkError("glTextureStorage2D");
  }
  width_ = width;
  height_ = height;
  layers_ = layers;
  format_ = internalFormat;
  for (int level = 0, w = width, h = height; level < levels; ++level, w = std::max(1, w / 2), h = std::max(1, h / 2)) {
    bytes_ += texel * static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(std::max(layers, 1));
  }
  account(static_cast<std::int64_t>(bytes_));
}

void Texture::release() {
  if (name_) account(-static_cast<std::int64_t>(bytes_));
  name_.reset();
  bytes_ = 0;
}

Texture::~Texture() { release(); }

Texture& Texture::operator=(Texture&& other) noexcept {
  if (this != &other) {
    release();
    name_ = std::move(other.name_);
    width_ = other.width_;
    height_ = other.height_;
    layers_ = other.layers_;
    format_ = other.format_;
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

Framebuffer::Framebuffer() {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  name_ = UniqueName<FramebufferDeleter>(id);
}

void Framebuffer::attach(GLenum attachment, const Texture& texture) {
  glNamedFramebufferTexture(id(), attachment, texture.id(), 0);
}

void Framebuffer::attachLayer(GLenum attachment, const Texture& texture, int layer) {
  glNamedFramebufferTextureLayer(id(), attachment, texture.id(), 0, layer);
}

void Framebuffer::checkComplete(const std::string& what) const {
  const GLenum status = glCheckNamedFramebufferStatus(id(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw Error(fmt::format("{}: framebuffer incomplete (status 0x{:04x})", what, status));
  }
}

VertexArray::VertexArray() {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  name_ = UniqueName<VertexArrayDeleter>(id);
}

Query::Query(GLenum target) : target_(target) {
  GLuint id = 0;
  glCreateQueries(target, 1, &id);
  name_ = UniqueName<QueryDeleter>(id);
}

}  // namespace forest::gl
