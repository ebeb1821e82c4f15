#include "forest/core/camera_path.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "toml_schema.hpp"

namespace forest {
namespace {

// Hermite tangent at key i of samples v over times t (finite-difference Catmull-Rom).
template <typename T>
T tangentAt(const std::vector<double>& t, const std::vector<T>& v, size_t i) {
  const size_t last = t.size() - 1;
  const size_t a = i == 0 ? 0 : i - 1;
  const size_t b = i == last ? last : i + 1;
  return (v[b] - v[a]) / (t[b] - t[a]);
}

// Cubic Hermite between (p0, m0) at t0 and (p1, m1) at t1, evaluated at s ∈ [0, 1].
template <typename T>
T hermite(const T& p0, const T& m0, const T& p1, const T& m1, double dt, double s) {
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * p0 + (h10 * dt) * m0 + h01 * p1 + (h11 * dt) * m1;
}

}  // namespace

CameraPath::CameraPath(std::vector<PathKey> keys, std::string name, bool aboveGround)
    : keys_(std::move(keys)), aboveGround_(aboveGround) {
  if (keys_.empty()) throw InputError(name + ": a camera path needs at least one [[key]]");
  for (size_t i = 0; i < keys_.size(); ++i) {
    const PathKey& k = keys_[i];
    const bool finite = std::isfinite(k.time) && std::isfinite(k.pose.yaw_deg) &&
                        std::isfinite(k.pose.pitch_deg) && std::isfinite(k.pose.position.x) &&
                        std::isfinite(k.pose.position.y) && std::isfinite(k.pose.position.z);
    if (!finite) throw InputError(fmt::format("{}: key[{}]: values must be finite", name, i));
    if (k.pose.pitch_deg < -90.0 || k.pose.pitch_deg > 90.0) {
      throw InputError(fmt::format("{}: key[{}].pitch_deg = {}: expected a number in [-90, 90]", name, i,
                                   k.pose.pitch_deg));
    }
    if (i > 0 && !(k.time > keys_[i - 1].time)) {
      throw InputError(fmt::format("{}: key[{}].t = {}: expected a time greater than key[{}].t = {}", name, i,
                                   k.time, i - 1, keys_[i - 1].time));
    }
  }
  unwrappedYaw_.resize(keys_.size());
  unwrappedYaw_[0] = keys_[0].pose.yaw_deg;
  for (size_t i = 1; i < keys_.size(); ++i) {
    double delta = std::remainder(keys_[i].pose.yaw_deg - keys_[i - 1].pose.yaw_deg, 360.0);
    unwrappedYaw_[i] = unwrappedYaw_[i - 1] + delta;
  }
  for (const PathKey& k : keys_) {
    times_.push_back(k.time);
    positions_.push_back(k.pose.position);
    pitches_.push_back(k.pose.pitch_deg);
  }
}

CameraPath CameraPath::parse(const std::string& text, const std::string& name) {
  const toml::table document = detail::parseToml(text, name);
  detail::TomlSection root(document, name, "");
  const bool aboveGround = root.oneOf("heights", std::string("absolute"), {"absolute", "above_ground"}) == "above_ground";
  std::vector<PathKey> keys;
  for (auto& s : root.tables("key")) {
    PathKey k;
    k.time = s.number("t", std::nullopt, detail::anyFinite());
    k.pose.position = s.vec3("position", std::nullopt, detail::anyFinite());
    k.pose.yaw_deg = s.number("yaw_deg", 0.0, detail::anyFinite());
    k.pose.pitch_deg = s.number("pitch_deg", 0.0, detail::closed(-90.0, 90.0));
    s.finish();
    keys.push_back(k);
  }
  root.finish();
  return CameraPath(std::move(keys), name, aboveGround);
}

CameraPath CameraPath::load(const std::filesystem::path& file) {
  return parse(readTextFile(file), file.string());
}

std::string CameraPath::toToml() const {
  toml::array keys;
  for (const PathKey& k : keys_) {
    keys.push_back(toml::table{{"t", k.time},
                               {"position", detail::tomlArray(k.pose.position)},
                               {"yaw_deg", k.pose.yaw_deg},
                               {"pitch_deg", k.pose.pitch_deg}});
  }
  std::ostringstream out;
  toml::table document{{"key", keys}};
  if (aboveGround_) document.insert("heights", "above_ground");
  out << document << "\n";
  return out.str();
}

CameraPose CameraPath::at(double time) const {
  if (keys_.size() == 1 || !(time > startTime())) {
    return {keys_.front().pose.position, unwrappedYaw_.front(), keys_.front().pose.pitch_deg};
  }
  if (time >= endTime()) return {keys_.back().pose.position, unwrappedYaw_.back(), keys_.back().pose.pitch_deg};

  const std::vector<double>& t = times_;
  const size_t i = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
  const double dt = t[i + 1] - t[i];
  const double s = (time - t[i]) / dt;
  CameraPose pose;
  pose.position = hermite(positions_[i], tangentAt(t, positions_, i), positions_[i + 1],
                          tangentAt(t, positions_, i + 1), dt, s);
  pose.yaw_deg = hermite(unwrappedYaw_[i], tangentAt(t, unwrappedYaw_, i), unwrappedYaw_[i + 1],
                         tangentAt(t, unwrappedYaw_, i + 1), dt, s);
  // The spline may overshoot between keys; pitch stays a valid elevation.
  pose.pitch_deg = std::clamp(hermite(pitches_[i], tangentAt(t, pitches_, i), pitches_[i + 1],
                                      tangentAt(t, pitches_, i + 1), dt, s),
                              -90.0, 90.0);
  return pose;
}

}  // namespace forest
