#pragma once
// GLSL programs from files in shaders/. The stage comes from the extension (.vert, .frag, .geom,
// .comp). Compile and link errors are reported as "file:line: message", one per line.
#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "forest/gl/objects.hpp"

namespace forest::gl {

struct ShaderSource {
  GLenum stage = 0;
  std::string name;  // used in error messages (usually the file path)
  std::string text;
};

class Program {
 public:
  Program() = default;
  explicit Program(GLuint id) : name_(id) {}
  GLuint id() const { return name_.id(); }
  void use() const { glUseProgram(id()); }

  // Uniform setters (glProgramUniform*); a name the linker removed is ignored. Locations come from
  // the table read once after linking (no glGetUniformLocation per call, DESIGN §9).
  void set(const char* uniform, int v) const;
  void set(const char* uniform, std::uint32_t v) const;
  void set(const char* uniform, float v) const;
  void set(const char* uniform, const glm::ivec2& v) const;
  void set(const char* uniform, const glm::vec2& v) const;
  void set(const char* uniform, const glm::vec3& v) const;
  void set(const char* uniform, const glm::vec4& v) const;
  void set(const char* uniform, const glm::mat3& v) const;
  void set(const char* uniform, const glm::mat4& v) const;
  // The uniform's location from the table (-1: not an active uniform).
  GLint location(std::string_view uniform) const;
  // Reads every active uniform's location (compileProgram does, after a successful link).
  void readUniformLocations();

 private:
  UniqueName<ProgramDeleter> name_;
  std::vector<std::pair<std::string, GLint>> locations_;  // sorted by name; arrays also as "a" for "a[0]"
};

// Folder the shaders are read from (core/resources.hpp: $FOREST_SHADER_DIR, installed, source tree).
std::filesystem::path shaderDirectory();

// Compiles and links; throws forest::Error with "name:line: message" lines.
Program compileProgram(const std::vector<ShaderSource>& sources);

// A shader file's text (relative to shaderDirectory() unless absolute), e.g. a block declaration
// to pass to loadProgram's `defines`.
std::string readShader(const std::string& file);

// Reads `files` (relative to shaderDirectory() unless absolute) and compiles them. `defines` are
// inserted after the #version line ("#define A 1\n..."), keeping line numbers right. An entry
// "a.frag+b.glsl" also inserts b.glsl's text there, into a.frag alone: functions shared by files
// of different programs, which a stage linking two copies would refuse.
Program loadProgram(const std::vector<std::string>& files, const std::string& defines = "");

// Rewrites a driver info log (Mesa "0:12(5): error: ...", NVIDIA "0(12) : error C...") into
// "name:12: error: ..." lines. Lines it does not recognise are kept, prefixed by "name: ".
std::string formatShaderLog(const std::string& name, const std::string& log);

}  // namespace forest::gl
