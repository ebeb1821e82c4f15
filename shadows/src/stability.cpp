#include "forest/shadows/stability.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/random.hpp"
#include "forest/shadows/focus_body.hpp"

namespace forest::shadows {
namespace {

using glm::dvec3;
using nlohmann::json;

// ---- case files ----

// Reads the fields of one case, naming the case in every error.
class CaseReader {
 public:
  CaseReader(const json& object, std::string where) : object_(object), where_(std::move(where)) {
    if (!object_.is_object()) fail("case", "expected an object");
    for (const auto& [key, value] : object_.items()) {
      if (std::find(std::begin(kKnownKeys), std::end(kKnownKeys), key) == std::end(kKnownKeys))
        fail(key, "unknown field (known: name, eye, view_dir, up, fovy_deg, aspect, near, far, sun_dir, "
                  "scene_min, scene_max, receivers, n_far, map_size, border_texels)");
    }
  }

  [[noreturn]] void fail(std::string_view field, std::string_view expected) const {
    throw InputError(fmt::format("{}: {}: {}", where_, field, expected));
  }

  const json& required(const char* field) const {
    if (!object_.contains(field)) fail(field, "missing");
    return object_.at(field);
  }

  double number(const char* field, const json& value) const {
    if (!value.is_number()) fail(field, fmt::format("expected a number, got {}", value.dump()));
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(field, "expected a finite number");
    return v;
  }
  double number(const char* field) const { return number(field, required(field)); }

  dvec3 vec3(const char* field, const json& value) const {
    if (!value.is_array() || value.size() != 3)
      fail(field, fmt::format("expected [x, y, z], got {}", value.dump()));
    return {number(field, value[0]), number(field, value[1]), number(field, value[2])};
  }
  dvec3 vec3(const char* field) const { return vec3(field, required(field)); }

  int integer(const char* field, int fallback) const {
    if (!object_.contains(field)) return fallback;
    const json& value = object_.at(field);
    if (!value.is_number_integer()) fail(field, fmt::format("expected an integer, got {}", value.dump()));
    return value.get<int>();
  }

  const json& object() const { return object_; }
  const std::string& where() const { return where_; }

 private:
  static constexpr const char* kKnownKeys[] = {"name", "eye", "view_dir", "up", "fovy_deg", "aspect",
                                               "near", "far", "sun_dir", "scene_min", "scene_max",
                                               "receivers", "n_far", "map_size", "border_texels"};
  const json& object_;
  std::string where_;
};

StabilityCase parseCase(const json& object, const std::string& where) {
  const CaseReader r(object, where);
  StabilityCase c;
  const json& name = r.required("name");
  if (!name.is_string()) r.fail("name", "expected a string");
  c.name = name.get<std::string>();
  const CaseReader named(object, fmt::format("{} ('{}')", where, c.name));

  Camera& camera = c.input.camera;
  camera.position = named.vec3("eye");
  try {
    camera.orient(named.vec3("view_dir"), named.vec3("up"));
  } catch (const InputError& e) {
    named.fail("view_dir, up", e.what());
  }
  const double fovyDeg = named.number("fovy_deg");
  if (!(fovyDeg > 0.0 && fovyDeg < 180.0)) named.fail("fovy_deg", fmt::format("expected 0 < fovy_deg < 180, got {}", fovyDeg));
  camera.fovy = glm::radians(fovyDeg);
  camera.aspect = named.number("aspect");
  if (!(camera.aspect > 0.0)) named.fail("aspect", fmt::format("expected a number > 0, got {}", camera.aspect));
  camera.near = named.number("near");
  if (!(camera.near > 0.0)) named.fail("near", fmt::format("expected a number > 0, got {}", camera.near));
  camera.far = named.number("far");
  if (!(camera.far > camera.near))
    named.fail("far", fmt::format("expected far > near ({}), got {}", camera.near, camera.far));

  c.input.sunDirection = named.vec3("sun_dir");
  if (glm::length(c.input.sunDirection) == 0.0) named.fail("sun_dir", "expected a non-zero direction");
  c.input.scene = Aabb{named.vec3("scene_min"), named.vec3("scene_max")};
  if (!c.input.scene.valid()) named.fail("scene_min, scene_max", "expected scene_min <= scene_max on every axis");

  if (object.contains("receivers")) {
    const json& receivers = object.at("receivers");
    if (!receivers.is_array() || receivers.empty())
      named.fail("receivers", "expected a non-empty array of {\"min\": [x, y, z], \"max\": [x, y, z]}");
    Aabb all;
    for (const json& box : receivers) {
      if (!box.is_object() || !box.contains("min") || !box.contains("max"))
        named.fail("receivers", fmt::format("expected {{\"min\": [x, y, z], \"max\": [x, y, z]}}, got {}", box.dump()));
      const Aabb b{named.vec3("receivers.min", box.at("min")), named.vec3("receivers.max", box.at("max"))};
      if (!b.valid()) named.fail("receivers", "expected min <= max on every axis");
      all.extend(b);
    }
    c.input.receivers = all;
  }
  if (object.contains("n_far")) c.input.nFar = named.number("n_far");
  c.input.mapSize = named.integer("map_size", c.input.mapSize);
  c.input.borderTexels = named.integer("border_texels", c.input.borderTexels);
  try {
    validateShadowInput(c.input);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", named.where(), e.what()));
  }
  return c;
}

// ---- random cases ----

// A fixed, portable stream with a random direction on top.
class Random : public SplitMix64 {
 public:
  using SplitMix64::SplitMix64;
  dvec3 direction() {
    const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * std::numbers::pi);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), z, r * std::sin(phi)};
  }
};

// Turns `direction` by `angle` radians towards some direction perpendicular to it.
dvec3 tilted(const dvec3& direction, double angle, Random& random) {
  dvec3 side = glm::cross(direction, random.direction());
  if (glm::length(side) < 1e-6) side = glm::cross(direction, dvec3(1, 0, 0));
  if (glm::length(side) < 1e-6) side = glm::cross(direction, dvec3(0, 0, 1));
  side = glm::normalize(side);
  return std::cos(angle) * direction + std::sin(angle) * side;
}

dvec3 randomPointIn(const Aabb& box, Random& random) {
  return {random.uniform(box.min.x, box.max.x), random.uniform(box.min.y, box.max.y),
          random.uniform(box.min.z, box.max.z)};
}

}  // namespace

std::vector<StabilityCase> parseStabilityCases(std::string_view text, const std::string& source) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(fmt::format("{}: invalid JSON at byte {}: {}", source, e.byte, e.what()));
  } catch (const json::exception& e) {  // e.g. a number too large for a double
    throw InputError(fmt::format("{}: invalid JSON: {}", source, e.what()));
  }
  const json* list = &document;
  if (document.is_object() && document.contains("cases")) list = &document.at("cases");
  if (!list->is_array()) throw InputError(fmt::format("{}: expected an array of cases (or {{\"cases\": [...]}})", source));
  std::vector<StabilityCase> cases;
  for (size_t i = 0; i < list->size(); ++i) cases.push_back(parseCase((*list)[i], fmt::format("{}: case {}", source, i + 1)));
  return cases;
}

std::vector<StabilityCase> loadStabilityCases(const std::filesystem::path& file) {
  return parseStabilityCases(readTextFile(file), file.string());
}

StabilityCase randomStabilityCase(std::uint64_t seed, std::uint64_t index) {
  Random random(SplitMix64::substream(seed, index));
  random.next();
  StabilityCase c;
  c.name = fmt::format("random {} #{}", seed, index);
  ShadowInput& in = c.input;

  // S: 10 m to 10 km per axis, sometimes flat or thin, sometimes 10⁶ m from the origin.
  const dvec3 centre = random.chance(0.1) ? dvec3(random.uniform(-1e6, 1e6), random.uniform(-100, 100), random.uniform(-1e6, 1e6))
                                          : dvec3(random.uniform(-1e3, 1e3), random.uniform(-50, 50), random.uniform(-1e3, 1e3));
  dvec3 half(random.logUniform(5, 5e3), random.logUniform(1, 500), random.logUniform(5, 5e3));
  if (random.chance(0.1)) half.y = 0.0;
  if (random.chance(0.05)) half.x = random.logUniform(1e-3, 1.0);
  in.scene = Aabb{centre - half, centre + half};

  // Sun: mostly above the horizon, down to grazing 0.05°; sometimes below it; any length.
  const double azimuth = random.uniform(0.0, 2.0 * std::numbers::pi);
  double elevation = random.chance(0.15) ? glm::radians(random.uniform(0.05, 0.5)) : std::asin(random.uniform(0.0, 1.0));
  if (random.chance(0.05)) elevation = -elevation;
  dvec3 sun(std::cos(elevation) * std::cos(azimuth), -std::sin(elevation), std::cos(elevation) * std::sin(azimuth));
  if (random.chance(0.05)) sun *= random.logUniform(1e-3, 1e3);
  const dvec3 l = glm::normalize(sun);

  // View: any direction; sometimes (anti-)parallel to the light, exactly or within 1e-7…1e-3 rad,
  // or straight up or down.
  dvec3 view = random.direction();
  const double pick = random.unit();
  if (pick < 0.05) view = random.chance(0.5) ? l : -l;
  else if (pick < 0.15) view = tilted(random.chance(0.5) ? l : -l, random.logUniform(1e-7, 1e-3), random);
  else if (pick < 0.2) view = dvec3(0, random.chance(0.5) ? 1 : -1, 0);
  dvec3 up = random.direction();
  while (glm::length(glm::cross(up, view)) < 1e-3) up = random.direction();
  if (random.chance(0.7)) up = dvec3(0, 1, 0) + 1e-6 * up;  // nearly always a level horizon in practice
  if (glm::length(glm::cross(up, view)) < 1e-3) up = glm::cross(view, random.direction());

  Camera& camera = in.camera;
  camera.orient(view, up);
  camera.fovy = glm::radians(random.logUniform(0.5, 170.0));
  camera.aspect = random.logUniform(0.1, 10.0);
  camera.near = random.logUniform(1e-4, 1.0);
  camera.far = camera.near * random.logUniform(2.0, 1e6);

  // Eye: inside S, or outside it looking anywhere (B may be empty).
  const Aabb inflated{in.scene.min - dvec3(1.0), in.scene.max + dvec3(1.0)};
  camera.position = random.chance(0.85) ? randomPointIn(in.scene, random)
                                        : in.scene.centre() + random.direction() * inflated.diagonal() * random.uniform(0.6, 3.0);

  if (random.chance(0.3)) {
    Aabb receivers;
    const int count = 1 + static_cast<int>(random.unit() * 5);
    for (int i = 0; i < count; ++i) {
      const dvec3 a = randomPointIn(in.scene, random), b = randomPointIn(in.scene, random);
      receivers.extend(Aabb{glm::min(a, b), glm::max(a, b)});
    }
    in.receivers = receivers;
  }
  if (random.chance(0.2)) in.nFar = camera.near + (camera.far - camera.near) * random.uniform(0.05, 1.0);
  in.mapSize = 1 << static_cast<int>(random.uniform(9.0, 14.0));
  in.borderTexels = static_cast<int>(random.uniform(0.0, 4.0));
  return c;
}

bool StabilityReport::passed() const {
  return std::all_of(checks.begin(), checks.end(), [](const InvariantCheck& c) { return c.passed; });
}

StabilityReport checkSetupInvariants(const ShadowInput& in, ShadowMethod method, const ShadowSetup& setup) {
  StabilityReport report;
  auto check = [&](const char* name) -> InvariantCheck& { return report.checks.emplace_back(InvariantCheck{name, true, {}}); };

  InvariantCheck& finite = check("finite");
  for (const glm::mat4* m : {&setup.worldToShadowClipF, &setup.eyeRelativeToShadowClipF})
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite((*m)[c][r])) {
          finite.passed = false;
          finite.detail = fmt::format("matrix entry [{}][{}] = {}", c, r, (*m)[c][r]);
        }
  for (int c = 0; c < 4; ++c)
    if (!std::isfinite(setup.eyeRelativeToLightDepthF[c])) {
      finite.passed = false;
      finite.detail = fmt::format("light depth row entry [{}] = {}", c, setup.eyeRelativeToLightDepthF[c]);
    }
  if (!finite.passed) return report;

  // The GPU's view of a world point: float32 camera-relative position, float32 arithmetic.
  const dvec3 eye = in.camera.position;
  auto onGpu = [&](const dvec3& world, float& w) {
    const glm::vec4 relative(glm::vec3(world - eye), 1.0f);
    const glm::vec4 h = setup.eyeRelativeToShadowClipF * relative;
    w = h.w;
    glm::vec3 p = glm::vec3(h) / h.w;
    if (setup.linearDepth) p.z = glm::dot(setup.eyeRelativeToLightDepthF, relative);  // tsm (TSM §4)
    return p;
  };

  InvariantCheck& body = check("body in map");
  for (const dvec3& v : setup.body.vertices()) {
    float w = 0.0f;
    const glm::vec3 p = onGpu(v, w);
    const double m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    report.maxMapCoordinate = std::max(report.maxMapCoordinate, m);
    if (body.passed && (!(w > 0.0f) || !(m <= 1.0))) {
      body.passed = false;
      body.detail = fmt::format("vertex ({}, {}, {}) maps to ({}, {}, {}), w = {}", v.x, v.y, v.z, p.x, p.y, p.z, w);
    }
  }

  // V ∩ S (∩ receivers) is inside B, so inside the map; checked on its own vertices, which the
  // clipper computes separately (up to the body tolerance, 1e-9 of its size: kVisibleTolerance).
  constexpr double kVisibleTolerance = 1e-6;
  InvariantCheck& visible = check("visible in map");
  ConvexBody seen = viewFrustumBody(in.camera);
  seen.clip(in.scene);
  if (in.receivers) seen.clip(*in.receivers);
  if (!seen.empty() && setup.empty) {
    visible.passed = false;
    visible.detail = "V ∩ S is not empty but the setup says there is nothing to shadow";
  }
  if (!setup.empty) {
    for (const dvec3& v : seen.vertices()) {
      float w = 0.0f;
      const glm::vec3 p = onGpu(v, w);
      if (!(w > 0.0f) || !(std::max(std::abs(p.x), std::abs(p.y)) <= 1.0 + kVisibleTolerance)) {
        visible.passed = false;
        visible.detail = fmt::format("visible vertex ({}, {}, {}) maps to ({}, {}), w = {}", v.x, v.y, v.z, p.x, p.y, w);
        break;
      }
    }
  }

  if (method == ShadowMethod::Lispsm && !setup.empty) {
    InvariantCheck& n = check("n valid");
    const ShadowDiagnostics& d = setup.diagnostics;
    if (!(d.n > 0.0) || !std::isfinite(d.n) || !(d.warp >= 0.0) || !std::isfinite(d.warp)) {
      n.passed = false;
      n.detail = fmt::format("n = {}, warp = {}", d.n, d.warp);
    } else if (!(d.n <= d.nCap) || !std::isfinite(d.nCap)) {
      n.passed = false;
      n.detail = fmt::format("n = {} above the cap {}", d.n, d.nCap);
    }
  }
  return report;
}

}  // namespace forest::shadows
