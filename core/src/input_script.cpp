#include "forest/core/input_script.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "toml_schema.hpp"

namespace forest {

InputScript InputScript::parse(const std::string& text, const std::string& name, const std::vector<std::string>& keyNames) {
  const toml::table document = detail::parseToml(text, name);
  detail::TomlSection root(document, name, "");
  InputScript script;
  for (auto& s : root.tables("event")) {
    InputEvent e;
    e.time = s.number("t", std::nullopt, detail::nonNegative());
    const int kinds = int(s.has("key")) + int(s.has("look")) + int(s.has("quit"));
    if (kinds != 1)
      s.fail(nullptr, "", fmt::format("an event needs exactly one of key, look and quit (found {})", kinds));
    if (s.has("key")) {
      e.kind = InputEvent::Kind::Key;
      e.key = s.oneOf("key", std::nullopt, keyNames);
      const std::string action = s.oneOf("action", std::string("tap"), {"press", "release", "tap"});
      e.action = action == "press" ? InputEvent::Action::Press
                 : action == "release" ? InputEvent::Action::Release
                                       : InputEvent::Action::Tap;
    } else if (s.has("look")) {
      e.kind = InputEvent::Kind::Look;
      e.look = s.vec2("look", std::nullopt, detail::closed(-1e5, 1e5));
    } else {
      e.kind = InputEvent::Kind::Quit;
      if (!s.boolean("quit", std::nullopt)) s.fail(nullptr, "quit", "expected true (leave the event out otherwise)");
    }
    s.finish();
    if (!script.events_.empty() && e.time < script.events_.back().time)
      s.fail(nullptr, "t", fmt::format("{} is before the previous event's t = {}: expected times that never decrease", e.time,
                                       script.events_.back().time));
    script.events_.push_back(std::move(e));
  }
  root.finish();
  return script;
}

InputScript InputScript::load(const std::filesystem::path& file, const std::vector<std::string>& keyNames) {
  return parse(readTextFile(file), file.string(), keyNames);
}

}  // namespace forest
