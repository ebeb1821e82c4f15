#pragma once
// Minimal leveled logging to stderr, with a replaceable sink (tests capture messages).
#include <fmt/format.h>

#include <functional>
#include <string>

namespace forest::log {

enum class Level { Debug, Info, Warning, Error };

using Sink = std::function<void(Level, const std::string&)>;

// Replaces the sink; returns the previous one. The default writes "[level] message" to stderr.
Sink setSink(Sink sink);
// Messages below this level are dropped (default Info; FOREST_LOG=debug lowers it).
void setMinimumLevel(Level level);
void write(Level level, const std::string& message);

template <typename... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) {
  write(Level::Debug, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void info(fmt::format_string<Args...> f, Args&&... args) {
  write(Level::Info, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void warn(fmt::format_string<Args...> f, Args&&... args) {
  write(Level::Warning, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void error(fmt::format_string<Args...> f, Args&&... args) {
  write(Level::Error, fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace forest::log
