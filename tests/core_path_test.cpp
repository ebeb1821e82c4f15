// Camera paths: keys round-trip; the Catmull-Rom spline passes through keys, reproduces constant
// velocity exactly, unwraps yaw; bad keys are rejected with the key named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "forest/core/camera_path.hpp"
#include "forest/core/error.hpp"
#include "forest/core/input_script.hpp"

namespace forest {
namespace {

using ::testing::HasSubstr;

constexpr const char* kPath = R"(
[[key]]
t = 0.0
position = [0.0, 2.0, 0.0]
yaw_deg = 350.0
pitch_deg = -5.0

[[key]]
t = 1.5
position = [3.0, 2.5, -4.0]
yaw_deg = 10.0

[[key]]
t = 4.0
position = [5.0, 1.0, -9.0]
yaw_deg = 40.0
pitch_deg = 20.0
)";

TEST(CameraPath, RoundTripsThroughToml) {
  const CameraPath path = CameraPath::parse(kPath, "walk.toml");
  const CameraPath back = CameraPath::parse(path.toToml(), "back.toml");
  ASSERT_EQ(back.keys().size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.keys()[i].time, path.keys()[i].time);
    EXPECT_EQ(back.keys()[i].pose.position, path.keys()[i].pose.position);
    EXPECT_EQ(back.keys()[i].pose.yaw_deg, path.keys()[i].pose.yaw_deg);
    EXPECT_EQ(back.keys()[i].pose.pitch_deg, path.keys()[i].pose.pitch_deg);
  }
}

TEST(CameraPath, PassesThroughEveryKey) {
  const CameraPath path = CameraPath::parse(kPath, "walk.toml");
  for (const PathKey& k : path.keys()) {
    const CameraPose p = path.at(k.time);
    EXPECT_NEAR(glm::distance(p.position, k.pose.position), 0.0, 1e-12);
    EXPECT_NEAR(std::remainder(p.yaw_deg - k.pose.yaw_deg, 360.0), 0.0, 1e-12);
    EXPECT_NEAR(p.pitch_deg, k.pose.pitch_deg, 1e-12);
  }
}

TEST(CameraPath, ReproducesConstantVelocityWithUnevenKeyTimes) {
  const glm::dvec3 start(1, 2, 3), velocity(0.5, -0.25, 2.0);
  std::vector<PathKey> keys;
  for (double t : {0.0, 0.3, 1.7, 2.0, 5.5}) keys.push_back({t, {start + t * velocity, 10.0 * t, 0.0}});
  const CameraPath path(keys);
  for (double t = 0.0; t <= 5.5; t += 0.05) {
    const CameraPose p = path.at(t);
    EXPECT_NEAR(glm::distance(p.position, start + t * velocity), 0.0, 1e-12) << t;
    EXPECT_NEAR(p.yaw_deg, 10.0 * t, 1e-11) << t;
  }
}

TEST(CameraPath, YawTakesTheShortWayRound) {
  const CameraPath path = CameraPath::parse(kPath, "walk.toml");
  // 350° → 10° is a 20° turn: halfway in time the yaw stays within that turn.
  const double mid = path.at(0.75).yaw_deg;
  EXPECT_GT(mid, 345.0);
  EXPECT_LT(mid, 375.0);
}

TEST(CameraPath, ClampsOutsideItsTimeRange) {
  const CameraPath path = CameraPath::parse(kPath, "walk.toml");
  EXPECT_EQ(path.at(-10.0).position, path.keys().front().pose.position);
  EXPECT_EQ(path.at(1e9).position, path.keys().back().pose.position);
}

TEST(CameraPath, SingleKeyIsAStillCamera) {
  const CameraPath path({{0.0, {{1, 2, 3}, 45.0, 0.0}}});
  EXPECT_EQ(path.at(7.0).position, glm::dvec3(1, 2, 3));
}

std::string errorOf(const std::string& text) {
  try {
    CameraPath::parse(text, "bad-path.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(CameraPath, BadInputIsNamed) {
  EXPECT_THAT(errorOf(""), HasSubstr("bad-path.toml: a camera path needs at least one [[key]]"));
  EXPECT_THAT(errorOf("[[key]]\nt = 1.0\nposition = [0,0,0]\n[[key]]\nt = 1.0\nposition = [1,0,0]\n"),
              HasSubstr("key[1].t = 1: expected a time greater than key[0].t = 1"));
  EXPECT_THAT(errorOf("[[key]]\nt = 0.0\nposition = [0,0,0]\npitch_deg = 95\n"),
              HasSubstr("key[0].pitch_deg = 95: expected a number in [-90, 90]"));
  EXPECT_THAT(errorOf("[[key]]\nt = nan\nposition = [0,0,0]\n"), HasSubstr("key[0].t = nan"));
  EXPECT_THAT(errorOf("[[key]]\nt = 0\nposition = [0,0,0]\nroll = 3\n"), HasSubstr("unknown key 'key[0].roll'"));
  EXPECT_THAT(errorOf("[[key]]\nposition = [0,0,0]\n"), HasSubstr("key[0].t: missing"));
}

const std::vector<std::string> kKeys = {"w", "c", "f"};

TEST(InputScript, ReadsKeysLooksAndQuit) {
  const InputScript script = InputScript::parse(R"(
[[event]]
t = 0.5
key = "w"
action = "press"
[[event]]
t = 0.5
look = [120.0, -30.0]
[[event]]
t = 1.25
key = "c"
[[event]]
t = 2.0
quit = true
)",
                                                "script.toml", kKeys);
  ASSERT_EQ(script.events().size(), 4u);
  EXPECT_EQ(script.events()[0].kind, InputEvent::Kind::Key);
  EXPECT_EQ(script.events()[0].key, "w");
  EXPECT_EQ(script.events()[0].action, InputEvent::Action::Press);
  EXPECT_EQ(script.events()[1].kind, InputEvent::Kind::Look);
  EXPECT_EQ(script.events()[1].look, glm::dvec2(120.0, -30.0));
  EXPECT_EQ(script.events()[2].action, InputEvent::Action::Tap);  // the default
  EXPECT_EQ(script.events()[3].kind, InputEvent::Kind::Quit);
  EXPECT_EQ(script.endTime(), 2.0);
}

TEST(InputScript, BadEventsAreNamed) {
  auto errorOf = [](const std::string& text) {
    try {
      InputScript::parse(text, "bad-script.toml", kKeys);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(errorOf("[[event]]\nt = 0\nkey = \"x\"\n"), HasSubstr("event[0].key = 'x': expected one of \"w\", \"c\", \"f\""));
  EXPECT_THAT(errorOf("[[event]]\nt = 0\nkey = \"w\"\nlook = [1, 2]\n"),
              HasSubstr("event[0]: an event needs exactly one of key, look and quit (found 2)"));
  EXPECT_THAT(errorOf("[[event]]\nt = 1\nquit = true\n[[event]]\nt = 0.5\nkey = \"w\"\n"),
              HasSubstr("event[1].t: 0.5 is before the previous event's t = 1"));
  EXPECT_THAT(errorOf("[[event]]\nt = -1\nkey = \"w\"\n"), HasSubstr("event[0].t = -1: expected a finite number >= 0"));
  EXPECT_THAT(errorOf("[[event]]\nt = 0\nkey = \"w\"\naction = \"hold\"\n"), HasSubstr("event[0].action"));
  EXPECT_THAT(errorOf("[[event]]\nt = 0\nlook = [1, nan]\n"), HasSubstr("event[0].look"));
  EXPECT_THAT(errorOf("[[event]]\nt = 0\nquit = false\n"), HasSubstr("event[0].quit: expected true"));
  EXPECT_THAT(errorOf("[[event]]\nt = 0\nkey = \"w\"\nwhen = 3\n"), HasSubstr("unknown key 'event[0].when'"));
}

}  // namespace
}  // namespace forest
