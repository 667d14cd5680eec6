// Camera path files: a path written by the recorder reads back equal; the interpolation passes
// through every keyframe, is continuous with a continuous first derivative at the keys, and frame
// times follow fps; bad files (table-driven) are refused with a message naming the file and the key.
#include <gtest/gtest.h>
#include <hr/types.h>

#include "camera_path.h"

namespace {

view::CameraPath threeKeys() {
  view::CameraPath p;
  p.fps = 24;
  p.keys = {{0.0, {0, 1, 5}, {0, 1, 0}, {0, 1, 0}, 45},
            {1.0, {2, 1, 4}, {0, 0.5, 0}, {0, 1, 0}, 40},
            {3.0, {3, 2, 0}, {0, 0.5, 0}, {0, 1, 0.1}, 50}};
  return p;
}

TEST(CameraPath, RoundTripsThroughJson) {
  view::CameraPath p = threeKeys();
  p.width = 640, p.height = 480;
  view::CameraPath q = view::parseCameraPath(view::cameraPathJson(p), "mem.json");
  ASSERT_EQ(q.keys.size(), p.keys.size());
  EXPECT_EQ(q.fps, p.fps);
  EXPECT_EQ(q.width, 640);
  for (std::size_t i = 0; i < p.keys.size(); ++i) {
    EXPECT_EQ(q.keys[i].time, p.keys[i].time);
    EXPECT_EQ(q.keys[i].eye, p.keys[i].eye);
    EXPECT_EQ(q.keys[i].lookAt, p.keys[i].lookAt);
    EXPECT_EQ(q.keys[i].fovYDeg, p.keys[i].fovYDeg);
  }
}

TEST(CameraPath, PassesThroughKeysSmoothly) {
  view::CameraPath p = threeKeys();
  for (const auto& k : p.keys) {
    hr::Camera c = view::cameraAt(p, k.time, 10, 10);
    EXPECT_LT(glm::length(c.eye - k.eye), 1e-12);
    EXPECT_LT(glm::length(c.lookAt - k.lookAt), 1e-12);
    EXPECT_NEAR(c.fovYDeg, k.fovYDeg, 1e-12);
  }
  // C1 at the inner key: the one-sided difference quotients agree (they would not for linear segments).
  const double h = 1e-5, t = p.keys[1].time;
  hr::Vec3 before = (view::cameraAt(p, t, 1, 1).eye - view::cameraAt(p, t - h, 1, 1).eye) / h;
  hr::Vec3 after = (view::cameraAt(p, t + h, 1, 1).eye - view::cameraAt(p, t, 1, 1).eye) / h;
  EXPECT_LT(glm::length(before - after), 1e-3 * glm::length(after));
  // Outside the span the path holds its end keys.
  EXPECT_EQ(view::cameraAt(p, -5.0, 1, 1).eye, p.keys.front().eye);
  EXPECT_EQ(view::cameraAt(p, 99.0, 1, 1).eye, p.keys.back().eye);
  // 3 s at 24 fps: frames at 0, 1/24, ..., 3.
  EXPECT_EQ(p.frameCount(), 73);
  EXPECT_DOUBLE_EQ(p.frameTime(72), 3.0);
}

struct BadPath {
  const char* name;
  const char* text;
  const char* key;  // what the message must name
};

void PrintTo(const BadPath& b, std::ostream* os) { *os << b.name; }

class BadPaths : public ::testing::TestWithParam<BadPath> {};

TEST_P(BadPaths, RefusedNamingFileAndKey) {
  const BadPath& b = GetParam();
  try {
    view::parseCameraPath(b.text, "walk.json");
    FAIL() << "accepted";
  } catch (const hr::InputError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("walk.json"), std::string::npos) << m;
    EXPECT_NE(m.find(b.key), std::string::npos) << m;
  }
}

#define KEY(t, e, a) "{\"time\": " #t ", \"eye\": " e ", \"look_at\": " a "}"
INSTANTIATE_TEST_SUITE_P(
    Table, BadPaths,
    ::testing::Values(BadPath{"not_json", "{\"keyframes\": [", "walk.json"},
                      BadPath{"no_keyframes", "{\"fps\": 30}", "keyframes"},
                      BadPath{"empty", "{\"keyframes\": []}", "keyframes"},
                      BadPath{"unknown_key", "{\"keyframes\": [" KEY(0, "[0,0,1]", "[0,0,0]") "], \"speed\": 2}", "speed"},
                      BadPath{"unknown_key_in_frame", "{\"keyframes\": [{\"time\": 0, \"eye\": [0,0,1], \"look_at\": [0,0,0], \"zoom\": 1}]}",
                              "keyframes[0].zoom"},
                      BadPath{"duplicate_key", "{\"keyframes\": [" KEY(0, "[0,0,1]", "[0,0,0]") "], \"fps\": 1, \"fps\": 2}", "fps"},
                      BadPath{"missing_eye", "{\"keyframes\": [{\"time\": 0, \"look_at\": [0,0,0]}]}", "keyframes[0].eye"},
                      BadPath{"time_backwards", "{\"keyframes\": [" KEY(1, "[0,0,1]", "[0,0,0]") ", " KEY(0.5, "[0,0,2]", "[0,0,0]") "]}",
                              "keyframes[1].time"},
                      BadPath{"eye_is_look_at", "{\"keyframes\": [" KEY(0, "[1,2,3]", "[1,2,3]") "]}", "keyframes[0].look_at"},
                      BadPath{"up_along_view", "{\"keyframes\": [{\"time\": 0, \"eye\": [0,5,0], \"look_at\": [0,0,0], \"up\": [0,1,0]}]}",
                              "keyframes[0].up"},
                      BadPath{"fov_too_wide", "{\"keyframes\": [{\"time\": 0, \"eye\": [0,0,1], \"look_at\": [0,0,0], \"fov_y_deg\": 200}]}",
                              "keyframes[0].fov_y_deg"},
                      BadPath{"eye_not_a_vector", "{\"keyframes\": [" KEY(0, "[0,1]", "[0,0,0]") "]}", "keyframes[0].eye"},
                      BadPath{"huge_coordinate", "{\"keyframes\": [" KEY(0, "[1e300,0,0]", "[0,0,0]") "]}", "keyframes[0].eye[0]"},
                      BadPath{"fps_zero", "{\"keyframes\": [" KEY(0, "[0,0,1]", "[0,0,0]") "], \"fps\": 0}", "fps"},
                      BadPath{"too_many_frames", "{\"keyframes\": [" KEY(0, "[0,0,1]", "[0,0,0]") ", " KEY(1e6, "[0,0,2]", "[0,0,0]") "], \"fps\": 100}", "fps"},
                      BadPath{"width_zero", "{\"keyframes\": [" KEY(0, "[0,0,1]", "[0,0,0]") "], \"width\": 0}", "width"}),
    [](const auto& tp) { return std::string(tp.param.name); });

}  // namespace
