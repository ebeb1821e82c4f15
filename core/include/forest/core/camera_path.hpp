#pragma once
// Camera paths: keys (time, position, yaw, pitch) interpolated with a Catmull-Rom spline.
// File format (TOML), see docs/scene-format.md:
//   [[key]]
//   t = 0.0                 # seconds, strictly increasing
//   position = [0, 2, 10]
//   yaw_deg = 0.0           # 0 looks along −z, positive turns left
//   pitch_deg = 0.0         # [−90, 90]
// and optionally, before the keys, heights = "absolute" (default) or "above_ground".
#include <glm/glm.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace forest {

struct CameraPose {
  glm::dvec3 position{0.0};
  double yaw_deg = 0.0;
  double pitch_deg = 0.0;
};

struct PathKey {
  double time = 0.0;
  CameraPose pose;
};

class CameraPath {
 public:
  // Validates the keys (at least one; finite; times strictly increasing; pitch in [−90, 90]).
  // `name` is used in error messages.
  explicit CameraPath(std::vector<PathKey> keys, std::string name = "<path>", bool aboveGround = false);

  static CameraPath load(const std::filesystem::path& file);
  static CameraPath parse(const std::string& text, const std::string& name);
  // TOML that parse() reads back to the same keys.
  std::string toToml() const;

  // Pose at `time`, clamped to [startTime, endTime]. Position, yaw and pitch each follow a
  // Catmull-Rom spline through the keys: Hermite segments with tangents
  // m_i = (p_{i+1} − p_{i−1}) / (t_{i+1} − t_{i−1}) (one-sided at the ends), so the path passes
  // through every key, is C¹, and reproduces motion at constant velocity exactly.
  // Yaw is unwrapped first, so 350° → 10° turns 20°, not 340°.
  CameraPose at(double time) const;

  // True when the file says `heights = "above_ground"`: position.y is metres over the terrain
  // (the host adds the ground height under the camera), not a world height.
  bool aboveGround() const { return aboveGround_; }

  double startTime() const { return keys_.front().time; }
  double endTime() const { return keys_.back().time; }
  // Frames of the path sampled at `fps` from its start, the end included when it falls on a frame.
  int frameCount(double fps) const { return 1 + static_cast<int>(std::floor((endTime() - startTime()) * fps + 1e-9)); }
  const std::vector<PathKey>& keys() const { return keys_; }

 private:
  std::vector<PathKey> keys_;
  // The keys split per channel once, for at(): times, positions, unwrapped yaw, pitch.
  std::vector<double> times_;
  std::vector<glm::dvec3> positions_;
  std::vector<double> unwrappedYaw_;
  std::vector<double> pitches_;
  bool aboveGround_ = false;
};

}  // namespace forest
