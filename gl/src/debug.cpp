#include "forest/gl/debug.hpp"

#include <fmt/format.h>

#include <atomic>
#include <deque>
#include <mutex>

#include "forest/core/log.hpp"
#include "forest/gl/gl.hpp"

namespace forest::gl {
namespace {

constexpr size_t kKeptMessages = 64;

struct DebugState {
  std::mutex mutex;
  std::atomic<std::uint64_t> errors{0};
  std::deque<std::string> messages;
};

DebugState& state() {
  static DebugState s;
  return s;
}

const char* typeName(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    default: return "other";
  }
}

void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                               const GLchar* message, const void* /*user*/) {
  const std::string text = fmt::format("GL {} #{}: {}", typeName(type), id,
                                       length >= 0 ? std::string(message, static_cast<size_t>(length))
                                                   : std::string(message));
  // Compiler diagnostics reach the caller as a ShaderError with file:line; they are not GL errors.
  if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) {
    log::debug("{}", text);
    return;
  }
  const bool isError = type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH;
  if (isError) {
    DebugState& s = state();
    s.errors.fetch_add(1);
    std::lock_guard lock(s.mutex);
    s.messages.push_back(text);
    if (s.messages.size() > kKeptMessages) s.messages.pop_front();
    log::error("{}", text);
  } else if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) {
    log::debug("{}", text);
  } else {
    log::warn("{}", text);
  }
}

}  // namespace

void enableDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // messages arrive on the calling thread, at the call
  glDebugMessageCallback(onDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

std::uint64_t debugErrorCount() { return state().errors.load(); }

std::vector<std::string> debugErrorMessages() {
  std::lock_guard lock(state().mutex);
  return {state().messages.begin(), state().messages.end()};
}

void resetDebugErrors() {
  std::lock_guard lock(state().mutex);
  state().errors = 0;
  state().messages.clear();
}

}  // namespace forest::gl
