#pragma once
// Input scripts: timed key and mouse events that drive the interactive window without a person
// (`forest walkthrough --window --script FILE`). File format (TOML), see docs/scene-format.md:
//   [[event]]
//   t = 0.5              # seconds of walk time, never decreasing
//   key = "w"            # one of the window's key names
//   action = "press"     # press | release | tap (press, then release on the next frame; default)
//   [[event]]
//   t = 1.0
//   look = [120, -30]    # mouse motion in pixels: x right, y down
//   [[event]]
//   t = 4.0
//   quit = true          # ends the run (the run also ends after the last event)
// Each event has exactly one of key, look and quit.
#include <glm/glm.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace forest {

struct InputEvent {
  enum class Kind { Key, Look, Quit };
  enum class Action { Press, Release, Tap };
  double time = 0.0;
  Kind kind = Kind::Key;
  std::string key;          // Kind::Key
  Action action = Action::Tap;
  glm::dvec2 look{0.0};     // Kind::Look, pixels
};

class InputScript {
 public:
  // `keyNames`: the keys the window binds; any other key name is an error that lists them.
  static InputScript parse(const std::string& text, const std::string& name, const std::vector<std::string>& keyNames);
  static InputScript load(const std::filesystem::path& file, const std::vector<std::string>& keyNames);

  const std::vector<InputEvent>& events() const { return events_; }
  // Time of the last event (0 for an empty script).
  double endTime() const { return events_.empty() ? 0.0 : events_.back().time; }

 private:
  std::vector<InputEvent> events_;
};

}  // namespace forest
