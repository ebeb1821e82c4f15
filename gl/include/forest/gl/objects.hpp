#pragma once
// RAII owners of GL objects (move-only; the name is deleted with the owner) and the count of GPU
// memory they allocated (buffers and textures; DESIGN §5 "report GPU memory").
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "forest/gl/gl.hpp"

namespace forest::gl {

// Bytes currently held by Buffer and Texture objects, and the peak since start.
struct GpuMemory {
  std::int64_t bytes = 0;
  std::int64_t peakBytes = 0;
};
GpuMemory gpuMemory();

// A GL name with a deleter; 0 = empty.
template <typename Deleter>
class UniqueName {
 public:
  UniqueName() = default;
  explicit UniqueName(GLuint id) : id_(id) {}
  ~UniqueName() { reset(); }
  UniqueName(UniqueName&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  UniqueName& operator=(UniqueName&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  UniqueName(const UniqueName&) = delete;
  UniqueName& operator=(const UniqueName&) = delete;

  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_ != 0) Deleter{}(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

struct BufferDeleter { void operator()(GLuint id) const; };
struct TextureDeleter { void operator()(GLuint id) const; };
struct FramebufferDeleter { void operator()(GLuint id) const; };
struct VertexArrayDeleter { void operator()(GLuint id) const; };
struct QueryDeleter { void operator()(GLuint id) const; };
struct ProgramDeleter { void operator()(GLuint id) const; };

// Immutable-storage buffer (glNamedBufferStorage).
class Buffer {
 public:
  Buffer() = default;
  Buffer(std::size_t bytes, const void* data, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
  ~Buffer();
  Buffer(Buffer&&) noexcept = default;
  Buffer& operator=(Buffer&& other) noexcept;

  GLuint id() const { return name_.id(); }
  std::size_t size() const { return bytes_; }
  // glNamedBufferSubData, bounds-checked.
  void upload(std::size_t offset, std::size_t bytes, const void* data);

 private:
  void release();
  UniqueName<BufferDeleter> name_;
  std::size_t bytes_ = 0;
};

// `count` unsigned integers, zeroed, in a buffer persistently and coherently mapped for reading:
// shaders write frame stamps into it (query results, the lighting pass's record of what showed),
// the CPU reads them once a client-mapped-buffer barrier and a fence after the writes signalled.
class ReadMappedStamps {
 public:
  ReadMappedStamps() = default;
  explicit ReadMappedStamps(std::size_t count);
  GLuint id() const { return buffer_.id(); }
  std::size_t size() const { return count_; }
  std::uint32_t operator[](std::size_t i) const { return stamps_[i]; }

 private:
  Buffer buffer_;
  const std::uint32_t* stamps_ = nullptr;
  std::size_t count_ = 0;
};

// Immutable-storage 2D texture (glTextureStorage2D), or a 2D array texture of `layers` layers
// (glTextureStorage3D; layers = 0: a plain 2D texture).
class Texture {
 public:
  Texture() = default;
  Texture(GLenum internalFormat, int width, int height, int levels = 1, int layers = 0);
  ~Texture();
  Texture(Texture&&) noexcept = default;
  Texture& operator=(Texture&& other) noexcept;

  GLuint id() const { return name_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }
  GLenum format() const { return format_; }
  int layers() const { return layers_; }  // 0: a 2D texture
  std::size_t bytes() const { return bytes_; }

 private:
  void release();
  UniqueName<TextureDeleter> name_;
  int width_ = 0, height_ = 0, layers_ = 0;
  GLenum format_ = 0;
  std::size_t bytes_ = 0;
};

// Bytes per texel of a sized internal format; throws forest::Error for formats not listed.
std::size_t bytesPerTexel(GLenum internalFormat);

class Framebuffer {
 public:
  Framebuffer();
  GLuint id() const { return name_.id(); }
  // Attaches level 0 of `texture` at `attachment` (GL_COLOR_ATTACHMENTi, GL_DEPTH_ATTACHMENT).
  void attach(GLenum attachment, const Texture& texture);
  // Attaches one layer of level 0 of an array texture.
  void attachLayer(GLenum attachment, const Texture& texture, int layer);
  // Throws forest::Error naming `what` unless complete.
  void checkComplete(const std::string& what) const;

 private:
  UniqueName<FramebufferDeleter> name_;
};

class VertexArray {
 public:
  VertexArray();
  GLuint id() const { return name_.id(); }

 private:
  UniqueName<VertexArrayDeleter> name_;
};

class Query {
 public:
  Query() = default;
  explicit Query(GLenum target);
  GLuint id() const { return name_.id(); }
  GLenum target() const { return target_; }

 private:
  UniqueName<QueryDeleter> name_;
  GLenum target_ = 0;
};

}  // namespace forest::gl
