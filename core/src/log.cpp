#include "forest/core/log.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace forest::log {
namespace {

const char* levelName(Level level) {
  switch (level) {
    case Level::Debug: return "debug";
    case Level::Info: return "info";
    case Level::Warning: return "warning";
    case Level::Error: return "error";
  }
  return "?";
}

void writeToStderr(Level level, const std::string& message) {
  std::fprintf(stderr, "[%s] %s\n", levelName(level), message.c_str());
}

Level initialMinimumLevel() {
  const char* env = std::getenv("FOREST_LOG");
  return env != nullptr && std::strcmp(env, "debug") == 0 ? Level::Debug : Level::Info;
}

struct State {
  std::mutex mutex;
  Sink sink = writeToStderr;
  Level minimum = initialMinimumLevel();
};

State& state() {
  static State s;
  return s;
}

}  // namespace

Sink setSink(Sink sink) {
  std::lock_guard lock(state().mutex);
  Sink previous = std::move(state().sink);
  state().sink = sink ? std::move(sink) : Sink(writeToStderr);
  return previous;
}

void setMinimumLevel(Level level) {
  std::lock_guard lock(state().mutex);
  state().minimum = level;
}

void write(Level level, const std::string& message) {
  std::lock_guard lock(state().mutex);
  if (level < state().minimum) return;
  state().sink(level, message);
}

}  // namespace forest::log
