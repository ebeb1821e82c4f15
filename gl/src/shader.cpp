#include "forest/gl/shader.hpp"

#include <fmt/format.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <cstring>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/resources.hpp"

namespace forest::gl {
namespace fs = std::filesystem;
namespace {

GLenum stageFromExtension(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".vert") return GL_VERTEX_SHADER;
  if (ext == ".frag") return GL_FRAGMENT_SHADER;
  if (ext == ".geom") return GL_GEOMETRY_SHADER;
  if (ext == ".comp") return GL_COMPUTE_SHADER;
  throw InputError(file.string() + ": unknown shader stage; expected .vert, .frag, .geom or .comp");
}

std::string infoLog(GLuint object, bool isProgram) {
  GLint length = 0;
  isProgram ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  isProgram ? glGetProgramInfoLog(object, length, nullptr, log.data())
            : glGetShaderInfoLog(object, length, nullptr, log.data());
  log.resize(std::strlen(log.c_str()));
  return log;
}

// Inserts `defines` after the #version line and resets the line count with #line.
std::string withDefines(const std::string& text, const std::string& defines) {
  if (defines.empty()) return text;
  const size_t versionAt = text.find("#version");
  if (versionAt == std::string::npos) return defines + "\n#line 1\n" + text;
  const size_t lineEnd = text.find('\n', versionAt);
  if (lineEnd == std::string::npos) return text + "\n" + defines;
  const int versionLine = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(lineEnd), '\n'));
  return text.substr(0, lineEnd + 1) + defines + "\n#line " + std::to_string(versionLine + 1) + "\n" +
         text.substr(lineEnd + 1);
}

// Line number and message of one info-log line in the Mesa ("0:12(5): error: ...") or NVIDIA
// ("0(12) : error C0000: ...") format; line 0 when the line has neither form.
std::pair<int, std::string> parseLogLine(const std::string& line) {
  int source = 0, lineNumber = 0, column = 0, consumed = 0;
  if (std::sscanf(line.c_str(), " %d:%d(%d):%n", &source, &lineNumber, &column, &consumed) == 3 && consumed > 0) {
    return {lineNumber, line.substr(static_cast<size_t>(consumed))};
  }
  consumed = 0;
  if (std::sscanf(line.c_str(), " %d(%d) :%n", &source, &lineNumber, &consumed) == 2 && consumed > 0) {
    return {lineNumber, line.substr(static_cast<size_t>(consumed))};
  }
  return {0, line};
}

}  // namespace

void Program::set(const char* uniform, int v) const { glProgramUniform1i(id(), location(uniform), v); }
void Program::set(const char* uniform, std::uint32_t v) const {
  glProgramUniform1ui(id(), location(uniform), v);
}
void Program::set(const char* uniform, float v) const { glProgramUniform1f(id(), location(uniform), v); }
void Program::set(const char* uniform, const glm::ivec2& v) const {
  glProgramUniform2i(id(), location(uniform), v.x, v.y);
}
void Program::set(const char* uniform, const glm::vec2& v) const {
  glProgramUniform2fv(id(), location(uniform), 1, glm::value_ptr(v));
}
void Program::set(const char* uniform, const glm::vec3& v) const {
  glProgramUniform3fv(id(), location(uniform), 1, glm::value_ptr(v));
}
void Program::set(const char* uniform, const glm::vec4& v) const {
  glProgramUniform4fv(id(), location(uniform), 1, glm::value_ptr(v));
}
void Program::set(const char* uniform, const glm::mat3& v) const {
  glProgramUniformMatrix3fv(id(), location(uniform), 1, GL_FALSE, glm::value_ptr(v));
}

void Program::set(const char* uniform, const glm::mat4& v) const {
  glProgramUniformMatrix4fv(id(), location(uniform), 1, GL_FALSE, glm::value_ptr(v));
}

void Program::readUniformLocations() {
  locations_.clear();
  GLint count = 0, longest = 0;
  glGetProgramInterfaceiv(id(), GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
  glGetProgramInterfaceiv(id(), GL_UNIFORM, GL_MAX_NAME_LENGTH, &longest);
  std::string name(static_cast<size_t>(std::max(1, longest)), '\0');
  for (GLint i = 0; i < count; ++i) {
    GLsizei length = 0;
    glGetProgramResourceName(id(), GL_UNIFORM, static_cast<GLuint>(i), static_cast<GLsizei>(name.size()), &length, name.data());
    const GLenum property = GL_LOCATION;
    GLint location = -1;
    glGetProgramResourceiv(id(), GL_UNIFORM, static_cast<GLuint>(i), 1, &property, 1, nullptr, &location);
    if (location < 0) continue;  // in a uniform block
    const std::string full(name.data(), static_cast<size_t>(length));
    locations_.emplace_back(full, location);
    // glGetUniformLocation("a") names an array's first element "a[0]" too.
    if (full.size() > 3 && full.compare(full.size() - 3, 3, "[0]") == 0) locations_.emplace_back(full.substr(0, full.size() - 3), location);
  }
  std::sort(locations_.begin(), locations_.end());
}

GLint Program::location(std::string_view uniform) const {
  const auto it = std::lower_bound(locations_.begin(), locations_.end(), uniform,
                                   [](const std::pair<std::string, GLint>& entry, std::string_view name) { return entry.first < name; });
  return it != locations_.end() && it->first == uniform ? it->second : -1;
}

std::string formatShaderLog(const std::string& name, const std::string& log) {
  std::istringstream lines(log);
  std::string line, out;
  while (std::getline(lines, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    auto [lineNumber, message] = parseLogLine(line);
    message.erase(0, message.find_first_not_of(' '));
    out += lineNumber > 0 ? fmt::format("{}:{}: {}\n", name, lineNumber, message)
                          : fmt::format("{}: {}\n", name, message);
  }
  if (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

fs::path shaderDirectory() { return resourceDirectory("shaders"); }

Program compileProgram(const std::vector<ShaderSource>& sources) {
  if (sources.empty()) throw Error("compileProgram: no shader sources");
  Program program(glCreateProgram());
  std::vector<GLuint> shaders;
  std::string errors;
  for (const ShaderSource& source : sources) {
    const GLuint shader = glCreateShader(source.stage);
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) errors += (errors.empty() ? "" : "\n") + formatShaderLog(source.name, infoLog(shader, false));
    shaders.push_back(shader);
  }
  if (errors.empty()) {
    for (GLuint shader : shaders) glAttachShader(program.id(), shader);
    glLinkProgram(program.id());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
      std::string names;
      for (const auto& s : sources) names += (names.empty() ? "" : "+") + s.name;
      errors = formatShaderLog(names, infoLog(program.id(), true));
    }
  }
  for (GLuint shader : shaders) glDeleteShader(shader);
  if (!errors.empty()) throw Error("shader error:\n" + errors);
  program.readUniformLocations();
  return program;
}

std::string readShader(const std::string& file) {
  const fs::path folder = shaderDirectory();
  const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : folder / file;
  try {
    return readTextFile(path);
  } catch (const InputError& e) {
    throw Error(fmt::format("shader {}: {} (shader folder: {}; set FOREST_SHADER_DIR to change it)", file, e.what(),
                            folder.string()));
  }
}

Program loadProgram(const std::vector<std::string>& files, const std::string& defines) {
  std::vector<ShaderSource> sources;
  for (const std::string& entry : files) {
    // "a.frag+b.glsl": a.frag with b.glsl's text after the defines, in that file alone.
    const size_t plus = entry.find('+');
    const std::string file = entry.substr(0, plus);
    std::string own = defines;
    for (size_t from = plus; from != std::string::npos;) {
      const size_t next = entry.find('+', from + 1);
      own += "\n" + readShader(entry.substr(from + 1, next == std::string::npos ? std::string::npos : next - from - 1));
      from = next;
    }
    const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : shaderDirectory() / file;
    sources.push_back({stageFromExtension(path), path.string(), withDefines(readShader(file), own)});
  }
  return compileProgram(sources);
}

}  // namespace forest::gl
