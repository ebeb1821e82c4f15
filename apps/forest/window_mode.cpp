// forest walkthrough --window: the interactive walkthrough in a GLFW window. Keyboard and mouse —
// or an input script, for runs without a person — move the camera and change the frame's settings;
// every frame goes into report.json with the settings it was rendered with and the stats line shown.
//
// Time: scripted runs advance exactly 1/fps per frame (so the recorded path and the report repeat
// from run to run); interactive runs advance by the measured frame time (at most 0.25 s a frame).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include "commands.hpp"
#include "run_output.hpp"
#include "forest/core/camera_path.hpp"
#include "forest/core/drawing.hpp"
#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/input_script.hpp"
#include "forest/core/log.hpp"
#include "forest/core/scene.hpp"
#include "forest/gl/context.hpp"
#include "forest/gl/debug.hpp"
#include "forest/render/frame.hpp"
#include "forest/render/overlay.hpp"

namespace forest::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Key names (the script's vocabulary) and their GLFW keys.
const std::map<std::string, int>& keyBindings() {
  static const std::map<std::string, int> keys = {
      {"w", GLFW_KEY_W},       {"a", GLFW_KEY_A},          {"s", GLFW_KEY_S},         {"d", GLFW_KEY_D},
      {"e", GLFW_KEY_E},       {"q", GLFW_KEY_Q},          {"shift", GLFW_KEY_LEFT_SHIFT}, {"ctrl", GLFW_KEY_LEFT_CONTROL},
      {"c", GLFW_KEY_C},       {"m", GLFW_KEY_M},          {"[", GLFW_KEY_LEFT_BRACKET}, {"]", GLFW_KEY_RIGHT_BRACKET},
      {"b", GLFW_KEY_B},       {"f", GLFW_KEY_F},          {"h", GLFW_KEY_H},         {"f1", GLFW_KEY_F1},
      {"left", GLFW_KEY_LEFT}, {"right", GLFW_KEY_RIGHT},  {"up", GLFW_KEY_UP},       {"down", GLFW_KEY_DOWN},
      {"tab", GLFW_KEY_TAB},   {"k", GLFW_KEY_K},          {"escape", GLFW_KEY_ESCAPE}};
  return keys;
}

std::vector<std::string> keyNames() {
  std::vector<std::string> names;
  for (const auto& [name, key] : keyBindings()) names.push_back(name);
  return names;
}

const std::vector<std::string> kHelp = {
    "W A S D  move          E / Q  up / down",
    "Shift  5x faster       Ctrl  5x slower",
    "mouse drag (or Tab: capture)  look",
    "C  culling strategy    M  shadow method",
    "[ / ]  shadow map size halved / doubled",
    "B  blur radius (0, 1.5, 3, 6 px)",
    "K  shadow cascades (1, 2, 3, 4 slices)",
    "Left / Right  sun azimuth -/+ 10 deg",
    "Up / Down  sun elevation +/- 5 deg",
    "F  freeze culling (keep the visible set)",
    "H or F1  this help     Esc  quit",
};

constexpr double kWalkSpeed = 6.0;         // m/s
constexpr double kLookDegreesPerPixel = 0.15;
constexpr double kMaxPitch = 89.0;
constexpr double kHeadroom = 0.3;          // metres kept above the terrain
const double kBlurSteps[] = {0.0, 1.5, 3.0, 6.0};

// Where the sun is, as the keys change it: azimuth from +x toward +z, elevation over the horizon.
struct SunAngles {
  double azimuthDeg = 0.0, elevationDeg = 45.0;
  static SunAngles of(const glm::dvec3& travel) {
    const glm::dvec3 s = -glm::normalize(travel);  // toward the sun
    return {glm::degrees(std::atan2(s.z, s.x)), glm::degrees(std::asin(std::clamp(s.y, -1.0, 1.0)))};
  }
  glm::dvec3 travel() const {
    const double az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    return -glm::dvec3(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
  }
};

// The name after `current` in `names`, wrapping round (the first for an unknown one).
std::string nextOf(const std::vector<std::string>& names, const std::string& current) {
  const auto it = std::find(names.begin(), names.end(), current);
  return it == names.end() || it + 1 == names.end() ? names.front() : *(it + 1);
}

// What the keys and the mouse change. Movement keys are held; the others act when pressed.
struct Controls {
  CameraPose pose;
  FrameOptions frame;  // culling, method, map size, blur (named as the command line names them)
  int cascades = 1;    // slices of the shadow map (set from the flags or the scene's [shadows])
  SunAngles sun;
  bool frozen = false;
  bool help = true;
  bool captured = false;  // interactive: the cursor is captured for mouse look
  bool quit = false;
  std::set<std::string> held;

  void press(const std::string& key) {
    held.insert(key);
    if (key == "c") {
      frame.culling = nextOf(culling::kCullingStrategyNames.names(), frame.culling);
    } else if (key == "m") {
      frame.method = nextOf(shadows::kShadowMethodNames.names(), frame.method);
    } else if (key == "[") {
      frame.shadowSize = std::max(512, frame.shadowSize / 2);
    } else if (key == "]") {
      frame.shadowSize = std::min(8192, frame.shadowSize * 2);
    } else if (key == "b") {
      auto next = std::find_if(std::begin(kBlurSteps), std::end(kBlurSteps), [&](double r) { return r > frame.blur; });
      frame.blur = next == std::end(kBlurSteps) ? 0.0 : *next;
    } else if (key == "k") {
      cascades = cascades % shadows::kMaxCascades + 1;
    } else if (key == "left" || key == "right") {
      sun.azimuthDeg = std::remainder(sun.azimuthDeg + (key == "left" ? -10.0 : 10.0), 360.0);
    } else if (key == "up" || key == "down") {
      sun.elevationDeg = std::clamp(sun.elevationDeg + (key == "up" ? 5.0 : -5.0), -10.0, 90.0);
    } else if (key == "f") {
      frozen = !frozen;
    } else if (key == "h" || key == "f1") {
      help = !help;
    } else if (key == "escape") {
      quit = true;
    }
  }
  void release(const std::string& key) { held.erase(key); }
  void look(glm::dvec2 pixels) {
    pose.yaw_deg -= kLookDegreesPerPixel * pixels.x;  // right turns right (positive yaw turns left)
    pose.pitch_deg = std::clamp(pose.pitch_deg - kLookDegreesPerPixel * pixels.y, -kMaxPitch, kMaxPitch);
  }
  // Moves by the held keys over dt seconds (horizontal moves follow the yaw, not the pitch).
  void move(double dt) {
    const double yaw = glm::radians(pose.yaw_deg);
    const glm::dvec3 forward(-std::sin(yaw), 0.0, -std::cos(yaw)), right(std::cos(yaw), 0.0, -std::sin(yaw));
    auto down = [&](const char* key) { return held.count(key) ? 1.0 : 0.0; };
    glm::dvec3 direction = forward * (down("w") - down("s")) + right * (down("d") - down("a")) +
                           glm::dvec3(0.0, 1.0, 0.0) * (down("e") - down("q"));
    if (glm::length(direction) == 0.0) return;
    const double speed = kWalkSpeed * (held.count("shift") ? 5.0 : 1.0) * (held.count("ctrl") ? 0.2 : 1.0);
    pose.position += glm::normalize(direction) * speed * dt;
  }
};

// GLFW callbacks queue events here; the frame loop applies them in order.
struct WindowInput {
  std::deque<InputEvent> events;
  std::map<int, std::string> names;  // GLFW key → key name
  bool dragging = false;
  bool captured = false;
  glm::dvec2 cursor{0.0};
  bool haveCursor = false;
};

void onKey(GLFWwindow* window, int key, int, int action, int) {
  auto* input = static_cast<WindowInput*>(glfwGetWindowUserPointer(window));
  if (key == GLFW_KEY_RIGHT_SHIFT) key = GLFW_KEY_LEFT_SHIFT;
  if (key == GLFW_KEY_RIGHT_CONTROL) key = GLFW_KEY_LEFT_CONTROL;
  const auto name = input->names.find(key);
  if (name == input->names.end() || action == GLFW_REPEAT) return;
  InputEvent e;
  e.key = name->second;
  e.action = action == GLFW_PRESS ? InputEvent::Action::Press : InputEvent::Action::Release;
  input->events.push_back(e);
}

void onMouseButton(GLFWwindow* window, int, int action, int) {
  static_cast<WindowInput*>(glfwGetWindowUserPointer(window))->dragging = action == GLFW_PRESS;
}

void onCursor(GLFWwindow* window, double x, double y) {
  auto* input = static_cast<WindowInput*>(glfwGetWindowUserPointer(window));
  const glm::dvec2 p(x, y);
  if (input->haveCursor && (input->dragging || input->captured)) {
    InputEvent e;
    e.kind = InputEvent::Kind::Look;
    e.look = p - input->cursor;
    input->events.push_back(e);
  }
  input->cursor = p;
  input->haveCursor = true;
}

// A text panel: white lines on a translucent dark band.
Image8 textPanel(const std::vector<std::string>& lines, int width, int size) {
  const int lineHeight = size + 5;
  Image8 panel(width, lineHeight * static_cast<int>(lines.size()) + 6, 4);
  for (size_t i = 0; i < panel.pixels.size(); i += 4) panel.pixels[i + 3] = 170;
  for (size_t k = 0; k < lines.size(); ++k)
    drawText(panel, {6, 3 + lineHeight * static_cast<int>(k) + size}, lines[k], glm::vec3(1.0f), size);
  return panel;
}

std::uint64_t hashOf(const std::vector<std::uint32_t>& ids) {  // FNV-1a
  std::uint64_t h = 1469598103934665603ull;
  for (std::uint32_t id : ids) h = (h ^ id) * 1099511628211ull;
  return h;
}

Image8 readWindow(int width, int height) {
  Image8 image(width, height, 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
  flipRows(image);  // GL's first row is the bottom one
  return image;
}

// The frame's input events applied to the controls: looks, quits, key presses and releases (taps
// are released after the frame); Tab captures the mouse when the window is driven by hand (`input`).
void applyEvents(const std::deque<InputEvent>& events, Controls& controls, std::vector<std::string>& tapped, WindowInput* input,
                 GLFWwindow* handle) {
  for (const InputEvent& e : events) {
    if (e.kind == InputEvent::Kind::Quit) controls.quit = true;
    if (e.kind == InputEvent::Kind::Look) controls.look(e.look);
    if (e.kind != InputEvent::Kind::Key) continue;
    if (e.action == InputEvent::Action::Release) {
      controls.release(e.key);
      continue;
    }
    controls.press(e.key);
    if (e.action == InputEvent::Action::Tap) tapped.push_back(e.key);
    if (e.key == "tab" && input) {
      input->captured = !input->captured;
      glfwSetInputMode(handle, GLFW_CURSOR, input->captured ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
    }
  }
}

std::string statsLineOf(double frameMs, const Controls& controls, const render::FrameStats& s) {
  return fmt::format(
      "{:.1f} ms | {} | {} {}{} | blur {} | visible {} | casters {} | tris {:.2f}M + {:.2f}M | n {:.3g} | z_f {:.0f} m | sun {:.0f}/{:.0f} deg{}",
      frameMs, controls.frame.culling, controls.frame.method, controls.cascades > 1 ? fmt::format("{}x", controls.cascades) : "",
      controls.frame.shadowSize, controls.frame.blur, s.visibleObjects, s.casterObjects, static_cast<double>(s.geometryTriangles) * 1e-6,
      static_cast<double>(s.shadowTriangles) * 1e-6, s.shadow.n, s.farDepth, controls.sun.azimuthDeg, controls.sun.elevationDeg,
      controls.frozen ? " | CULLING FROZEN" : "");
}

// The frame in the window's back buffer, the stats line along its bottom (one line where it fits,
// about 7 px a character at 13 px, else split before "visible") and the help panel when shown.
void showFrame(const render::Frame& frame, render::ImageOverlay& overlay, const std::string& statsLine, const Image8* help, int width,
               int height) {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  frame.presentTo(0, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  std::vector<std::string> statsLines{statsLine};
  const size_t split = statsLine.find(" | visible");
  if (static_cast<double>(statsLine.size()) * 7.0 > width && split != std::string::npos)
    statsLines = {statsLine.substr(0, split), statsLine.substr(split + 3)};
  const Image8 statsPanel = textPanel(statsLines, width, 13);
  overlay.draw(statsPanel, {0, height - statsPanel.height}, width, height);
  if (help) overlay.draw(*help, {0, 0}, width, height);
}

// A frame's record in the window's report.json: the walkthrough's, with the settings it was drawn
// with, a hash of its visible set and the stats line shown.
nlohmann::ordered_json windowRecord(nlohmann::ordered_json r, const Controls& controls, const std::vector<std::uint32_t>& visible,
                                    const std::string& statsLine) {
  r["settings"] = {{"culling", controls.frame.culling},     {"method", controls.frame.method},
                   {"shadow_size", controls.frame.shadowSize}, {"blur_px", controls.frame.blur},
                   {"sun_azimuth_deg", controls.sun.azimuthDeg}, {"sun_elevation_deg", controls.sun.elevationDeg},
                   {"frozen", controls.frozen},              {"help", controls.help}};
  r["visible_set_hash"] = fmt::format("{:016x}", hashOf(visible));
  r["stats_line"] = statsLine;
  return r;
}


// The walk's start, as the headless walkthrough's (the default walk's only where the scene has the
// terrain it follows; else none: the scene's camera).
std::optional<CameraPath> walkStart(const std::string& path, const Scene& scene) {
  std::optional<CameraPath> start;
  if (!path.empty() || scene.terrain) start = CameraPath::load(walkPathOr(path));
  if (start && start->aboveGround() && !scene.terrain) throw InputError(path + ": heights = \"above_ground\" needs a scene with [terrain]");
  return start;
}

// Where the window's camera starts: the walk's first key (heights over the ground where it says
// so), else the frame's start camera.
CameraPose startPose(const Camera& camera, const std::optional<CameraPath>& start, const render::Frame& frame) {
  if (!start) return {camera.position, glm::degrees(camera.yaw), glm::degrees(camera.pitch)};
  CameraPose pose = start->at(start->startTime());
  if (start->aboveGround()) pose.position.y += frame.terrain()->heightAt(pose.position.x, pose.position.z);
  return pose;
}

// The frame's settings as the keys left them; the term and the map are shown, never read back.
render::FrameSettings frameSettingsOf(const Controls& controls, const gl::ContextInfo& info) {
  render::FrameSettings settings = controls.frame.settings(info);
  settings.freezeCulling = controls.frozen;
  settings.keepShadowTerm = false;
  settings.wholeShadowMap = false;
  settings.cascades = controls.cascades;
  return settings;
}

// The window, its GL context and (interactive) its input callbacks, which fill `input`.
std::unique_ptr<gl::Context> openWindow(int width, int height, WindowInput& input, bool interactive) {
  gl::ContextOptions contextOptions;
  contextOptions.backend = gl::Backend::Window;
  contextOptions.width = width;
  contextOptions.height = height;
  contextOptions.title = "forest walkthrough";
  auto context = gl::createContext(contextOptions);
  log::info("{}", gl::describe(context->info()));
  GLFWwindow* handle = context->window();
  for (const auto& [name, key] : keyBindings()) input.names[key] = name;
  glfwSetWindowUserPointer(handle, &input);
  if (interactive) {
    glfwSetKeyCallback(handle, onKey);
    glfwSetMouseButtonCallback(handle, onMouseButton);
    glfwSetCursorPosCallback(handle, onCursor);
  }
  glfwSwapInterval(0);
  return context;
}

// What the report says of a window run besides its frames.
struct WindowRunInfo {
  std::string scenePath, script;  // script: "" when interactive
  std::string device;
  nlohmann::ordered_json settings;
  int warmup = 0, done = 0;
};

// report.json, window.png (the last frame shown; none when the window was closed), the camera path
// flown (--record), and the summary on stdout.
void writeWindowOutputs(const WalkthroughOptions& options, const WindowOptions& window, const WindowRunInfo& info,
                        const nlohmann::ordered_json& records, const Image8& shown, const std::vector<PathKey>& flown) {
  const fs::path out(options.out);
  const nlohmann::ordered_json summary = summariseFrames(records, info.done - std::min(info.done, info.warmup));
  nlohmann::ordered_json report;
  report["scene"] = info.scenePath;
  report["input"] = info.script.empty() ? "interactive" : info.script;
  report["device"] = info.device;
  report["resolution"] = {options.size.width, options.size.height};
  report["fps"] = options.fps;
  report["settings"] = info.settings;
  report["warmup_frames"] = info.warmup;
  report["frames_done"] = info.done;
  report["summary"] = summary;
  report["frames"] = records;
  writeFileAtomic(out / "report.json", report.dump(1) + "\n");
  if (shown.width > 0) writeImage(out / "window.png", shown);
  if (!window.record.empty() && !flown.empty()) writeFileAtomic(window.record, CameraPath(flown, window.record).toToml());
  std::cout << fmt::format("window: {} frames of {} ({})\n", info.done, info.scenePath,
                           info.script.empty() ? "interactive" : "scripted by " + info.script);
  printSummary(summary);
  std::cout << fmt::format("  wrote {}/report.json, {}/window.png{}\n", shownPath(out), shownPath(out),
                           window.record.empty() ? "" : ", the camera path " + window.record);
}

}  // namespace

int runWindow(const WalkthroughOptions& options, const WindowOptions& window) {
  // Input first: nothing is opened or written for a bad scene, path, script or flag.
  if (options.gl.backend != "auto" && options.gl.backend != "window")
    throw InputError(fmt::format("--gl {} with --window: the window mode needs the window backend", options.gl.backend));
  const std::string scenePath = sceneFileOr(options.scene);
  // Warm-up frames: --warmup when given; else the default, capped at half of a --frames run.
  const int warmup = options.length.warmupFor(options.length.frames > 0 ? options.length.frames : 1 << 30);
  Scene scene = loadScene(scenePath);
  const std::optional<CameraPath> start = walkStart(options.path, scene);
  std::optional<InputScript> script;
  if (!window.script.empty()) script = InputScript::load(window.script, keyNames());
  Controls controls;
  controls.frame = options.frame;
  controls.cascades = render::resolveCascades(controls.frame.settings(), scene).cascades;  // names checked before the window opens
  controls.sun = SunAngles::of(scene.sun.direction);
  scene.render.width = options.size.width;
  scene.render.height = options.size.height;

  WindowInput input;
  auto context = openWindow(options.size.width, options.size.height, input, !script);
  GLFWwindow* handle = context->window();
  render::Frame frame(scene, options.size.width, options.size.height);
  render::ImageOverlay overlay;
  const Image8 helpPanel = textPanel(kHelp, std::min(options.size.width, 380), 13);

  Camera camera = frame.startCamera();
  controls.pose = startPose(camera, start, frame);

  const fs::path out(options.out);
  clearEarlierWalk(out);  // the folder holds this run only
  fs::create_directories(out);
  nlohmann::ordered_json records = nlohmann::ordered_json::array();
  std::vector<PathKey> flown;
  std::vector<std::string> tapped;  // released after the frame they were pressed in
  size_t nextEvent = 0;
  double time = 0.0;
  auto last = Clock::now();
  Image8 shown;
  int done = 0;
  for (int f = 0;; ++f) {
    // Time and input for this frame.
    const auto now = Clock::now();
    const double dt = f == 0 ? 0.0 : script ? 1.0 / options.fps : std::min(0.25, std::chrono::duration<double>(now - last).count());
    last = now;
    time = script ? f / options.fps : time + dt;
    glfwPollEvents();
    if (glfwWindowShouldClose(handle)) break;
    std::deque<InputEvent> events;
    if (script) {
      for (; nextEvent < script->events().size() && script->events()[nextEvent].time <= time + 1e-9; ++nextEvent)
        events.push_back(script->events()[nextEvent]);
    } else {
      events.swap(input.events);
    }
    applyEvents(events, controls, tapped, script ? nullptr : &input, handle);
    // The frame of a quit event, of the script's last event or the --frames-th is the last one.
    const bool lastFrame = controls.quit || (script && nextEvent == script->events().size()) ||
                           (options.length.frames > 0 && f + 1 == options.length.frames);
    controls.move(dt);
    if (frame.terrain()) {
      const double ground = frame.terrain()->heightAt(controls.pose.position.x, controls.pose.position.z);
      controls.pose.position.y = std::max(controls.pose.position.y, ground + kHeadroom);
    }
    for (const std::string& key : tapped) controls.release(key);
    tapped.clear();

    // Render with this frame's settings and sun.
    const render::FrameSettings settings = frameSettingsOf(controls, context->info());
    scene.sun.direction = controls.sun.travel();
    camera.position = controls.pose.position;
    camera.yaw = glm::radians(controls.pose.yaw_deg);
    camera.pitch = glm::radians(controls.pose.pitch_deg);
    const auto frameStart = Clock::now();
    const render::FrameStats s = frame.render(camera, time, settings);
    const double frameMs = 1e3 * std::chrono::duration<double>(Clock::now() - frameStart).count();

    // Show it: the image, the stats line, the help.
    int width = 0, height = 0;
    glfwGetFramebufferSize(handle, &width, &height);
    const std::string statsLine = statsLineOf(frameMs, controls, s);
    if (width > 0 && height > 0) {
      showFrame(frame, overlay, statsLine, controls.help ? &helpPanel : nullptr, width, height);
      if (lastFrame) shown = readWindow(width, height);
      context->swapBuffers();
    }
    records.push_back(windowRecord(frameRecord(f, time, f < warmup, camera, controls.pose.yaw_deg, frameMs, s), controls,
                                   frame.visibleObjects(), statsLine));
    recordPassTimes(frame.takePassTimes(), records);
    if (flown.empty() || time > flown.back().time) flown.push_back({time, controls.pose});
    ++done;
    if (lastFrame) break;
  }
  if (gl::debugErrorCount() > 0)
    throw Error(fmt::format("{} GL errors in the window (first: {})", gl::debugErrorCount(), gl::debugErrorMessages().front()));

  recordPassTimes(frame.drainPassTimes(), records);
  const WindowRunInfo info{scenePath, script ? window.script : std::string(), gl::describe(context->info()),
                           options.frame.json(context->info(), scene), warmup, done};
  writeWindowOutputs(options, window, info, records, shown, flown);
  return 0;
}

}  // namespace forest::app
