// The interactive viewer driven by synthetic interactor events (as a person's keys and mouse reach
// it), in an offscreen window under xvfb-run: g toggles glossy / diffuse-only (diffuse pixels stay
// byte-identical, the reflector loses its highlight, a second g restores the first frame exactly);
// p picks the surface under the mouse (the reflector's leaf, its report, a lobe glyph in the frame;
// nothing on the background); r records the camera path while walking and dragging, and the file
// replays the motion; h shows the help, the HUD names its figures, f walks at constant height, c
// cycles the scene's cameras. GHR_KEEP_SHOTS=DIR keeps the screenshots for a person to look at.
#include <vtkCamera.h>
#include <vtkCommand.h>

#include <filesystem>

#include "test_dir.h"
#include "view_fixture.h"
#include "viewer.h"
#include "walkthrough.h"
#include "window.h"

namespace fs = std::filesystem;

namespace {

using namespace viewtest;

void key(vtkRenderWindowInteractor* i, const char* sym) {
  i->SetKeyEventInformation(0, 0, sym[1] ? 0 : sym[0], 1, sym);
  i->InvokeEvent(vtkCommand::KeyPressEvent);
  i->InvokeEvent(vtkCommand::CharEvent);
  i->InvokeEvent(vtkCommand::KeyReleaseEvent);
}

void keyAt(vtkRenderWindowInteractor* i, const char* sym, int x, int y) {
  i->SetEventInformation(x, y, 0, 0, sym[0], 1, sym);
  i->InvokeEvent(vtkCommand::KeyPressEvent);
  i->InvokeEvent(vtkCommand::CharEvent);
}

void drag(vtkRenderWindowInteractor* i, int x0, int y0, int x1, int y1) {
  i->SetEventInformation(x0, y0);
  i->InvokeEvent(vtkCommand::MouseMoveEvent);
  i->InvokeEvent(vtkCommand::LeftButtonPressEvent);
  for (int s = 1; s <= 8; ++s) {
    i->SetEventInformation(x0 + (x1 - x0) * s / 8, y0 + (y1 - y0) * s / 8);
    i->InvokeEvent(vtkCommand::MouseMoveEvent);
  }
  i->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
}

/// The viewer's screenshot (key s), read back; kept in GHR_KEEP_SHOTS when set.
Png shot(view::Viewer& v, const std::string& keep) {
  key(v.interactor(), "s");
  Png p = readPng(v.lastScreenshot());
  if (const char* dir = std::getenv("GHR_KEEP_SHOTS"))
    fs::copy_file(v.lastScreenshot(), fs::path(dir) / (keep + ".png"), fs::copy_options::overwrite_existing);
  fs::remove(v.lastScreenshot());
  return p;
}

/// Display coordinates (VTK's: y from the bottom) of a world point seen by cam.
std::array<int, 2> project(const hr::Camera& cam, const hr::Vec3& p) {
  hr::Vec3 f = glm::normalize(cam.lookAt - cam.eye), r = glm::normalize(glm::cross(f, cam.up)), u = glm::cross(r, f);
  hr::Vec3 d = p - cam.eye;
  double th = std::tan(0.5 * cam.fovYDeg * hr::kPi / 180.0), aspect = double(cam.width) / cam.height;
  double px = glm::dot(d, r) / glm::dot(d, f) / (th * aspect), py = glm::dot(d, u) / glm::dot(d, f) / th;
  return {int((px + 1.0) * 0.5 * cam.width), int((py + 1.0) * 0.5 * cam.height)};
}

struct Session {
  hr::Camera cam = camera({0.1, 1.3, -2.0}, {0.0, 0.6, 0.3}, 320, 240);
  std::unique_ptr<view::SceneView> scene;
  std::unique_ptr<view::Viewer> viewer;
  explicit Session(std::vector<hr::Camera> extra = {}) {
    view::requireDisplay();
    const auto& l = threeLights();
    scene = std::make_unique<view::SceneView>(l.sol, l.ext.get(), 20.0);
    view::ViewerOptions o;
    o.cameras = {cam};
    o.cameras.insert(o.cameras.end(), extra.begin(), extra.end());
    o.width = cam.width, o.height = cam.height;
    o.offscreen = true;
    o.screenshotDir = testutil::testDir().string();
    o.recordPath = (testutil::testDir() / "recorded.json").string();
    viewer = std::make_unique<view::Viewer>(*scene, o);
    viewer->render();
  }
};

TEST(ViewInteraction, GTogglesGlossyAndDiffuseOnly) {
  Session s;
  const auto& l = threeLights();
  Png glossy = shot(*s.viewer, "ab_glossy");
  key(s.viewer->interactor(), "g");
  EXPECT_FALSE(s.scene->glossyShown());
  EXPECT_NE(s.viewer->hudText().find("diffuse only"), std::string::npos);
  Png diffuse = shot(*s.viewer, "ab_diffuse_only");
  key(s.viewer->interactor(), "g");
  Png again = shot(*s.viewer, "ab_glossy_again");
  EXPECT_EQ(again.rgb, glossy.rgb) << "g twice restores the frame exactly";
  SampleTruth t = sampleTruth(l.sol, l.ext.get(), s.cam);
  std::size_t diffuseSame = 0, diffuseCount = 0, reflector = 0;
  double drop = 0.0;
  for (int y = 0; y < s.cam.height; ++y)
    for (int x = 0; x < s.cam.width; ++x) {
      if (t.uniform(x, y, false)) {
        ++diffuseCount;
        diffuseSame += std::equal(glossy.at(x, y), glossy.at(x, y) + 3, diffuse.at(x, y));
      } else if (t.uniform(x, y, true)) {
        ++reflector;
        drop += luminance8(glossy.at(x, y)) - luminance8(diffuse.at(x, y));
      }
    }
  ASSERT_GT(reflector, 100u);
  drop /= double(reflector);
  std::printf("A/B: %zu of %zu diffuse pixels identical; reflector (%zu pixels) mean luminance drop %.4f\n", diffuseSame,
              diffuseCount, reflector, drop);
  EXPECT_EQ(diffuseSame, diffuseCount) << "the diffuse list is the same in both displays";
  EXPECT_GT(drop, 0.05) << "diffuse-only drops the reflector's glossy light (linear display luminance)";
}

TEST(ViewInteraction, PPicksTheSurfaceAndShowsItsLobe) {
  Session s;
  const auto& l = threeLights();
  Png before = shot(*s.viewer, "pick_before");
  auto at = project(s.cam, {0.0, 0.6, 0.3});  // the reflector's centre
  ::testing::internal::CaptureStdout();
  keyAt(s.viewer->interactor(), "p", at[0], at[1]);
  std::string printed = ::testing::internal::GetCapturedStdout();
  ASSERT_NE(s.viewer->pickedLeaf(), hr::kNone) << printed;
  const hr::Patch& patch = l.sol.patches[l.sol.elements[s.viewer->pickedLeaf()].patch];
  EXPECT_EQ(l.sol.materials[patch.material].name, "reflector");
  EXPECT_TRUE(l.sol.elements[s.viewer->pickedLeaf()].leaf());
  EXPECT_NE(printed.find("material \"reflector\""), std::string::npos) << printed;
  EXPECT_NE(printed.find("directional coefficients"), std::string::npos) << printed;
  EXPECT_NE(printed.find("radiosity"), std::string::npos) << printed;
  ASSERT_TRUE(s.viewer->glyph());
  Png after = shot(*s.viewer, "pick_glyph");
  std::size_t changed = 0;
  for (std::size_t i = 0; i < after.rgb.size(); i += 3) changed += !std::equal(&after.rgb[i], &after.rgb[i] + 3, &before.rgb[i]);
  std::printf("pick: element %u; the glyph changed %zu pixels\n", s.viewer->pickedLeaf(), changed);
  EXPECT_GT(changed, 100u) << "the lobe glyph is drawn (a narrow lobe: a spike of some 30 x 20 pixels here)";
  keyAt(s.viewer->interactor(), "p", 2, s.cam.height - 3);  // the black space above the floor
  EXPECT_EQ(s.viewer->pickedLeaf(), hr::kNone);
  EXPECT_FALSE(s.viewer->glyph());
}

TEST(ViewInteraction, RRecordsTheCameraPathForReplay) {
  Session s;
  auto* i = s.viewer->interactor();
  key(i, "r");
  EXPECT_TRUE(s.viewer->recording());
  key(i, "w");
  key(i, "w");
  key(i, "d");
  drag(i, 160, 120, 200, 130);
  hr::Camera end = s.scene->camera(s.cam.width, s.cam.height);
  key(i, "r");
  EXPECT_FALSE(s.viewer->recording());
  const std::string file = (testutil::testDir() / "recorded.json").string();
  ASSERT_TRUE(fs::exists(file));
  view::CameraPath p = view::loadCameraPath(file);
  EXPECT_GE(p.keys.size(), 5u) << "the start, three steps and the drag's frames";
  EXPECT_EQ(p.width, s.cam.width);
  EXPECT_LT(glm::length(p.keys.front().eye - s.cam.eye), 1e-9);
  hr::Camera replayEnd = view::cameraAt(p, p.keys.back().time, s.cam.width, s.cam.height);
  EXPECT_LT(glm::length(replayEnd.eye - end.eye), 1e-9);
  EXPECT_LT(glm::length(replayEnd.lookAt - end.lookAt), 1e-9);
  std::printf("recorded %zu keyframes over %.3f s\n", p.keys.size(), p.duration());
  // Replayed headless, the recording's last frame shows what the window showed at the end.
  Png live = shot(*s.viewer, "record_end");
  fs::path frames = testutil::testDir() / "replay";
  view::CameraPath last = p;
  last.keys = {p.keys.back()};
  last.keys[0].time = 0.0;
  view::runWalkthrough(*s.scene, last, s.cam.width, s.cam.height, {frames.string(), "", false, true});
  Png replay = readPng((frames / "frame_00000.png").string());
  ASSERT_EQ(replay.rgb.size(), live.rgb.size());
  std::size_t differ = 0;
  for (std::size_t k = 0; k < live.rgb.size(); ++k) differ += std::abs(int(live.rgb[k]) - int(replay.rgb[k])) > 1;
  EXPECT_EQ(differ, 0u) << "the replayed frame is the live one";
}

TEST(ViewInteraction, HelpHudWalkAndCameras) {
  hr::Camera second = camera({0, 1.6, 5.5}, {0, 1.1, -3}, 320, 240);
  Session s({second});
  auto* i = s.viewer->interactor();
  std::vector<unsigned char> plain = view::grabFrame(s.viewer->window());
  key(i, "h");
  EXPECT_TRUE(s.viewer->helpShown());
  std::vector<unsigned char> helpFrame = view::grabFrame(s.viewer->window());
  EXPECT_NE(helpFrame, plain) << "the help is drawn";
  keep(Png{s.cam.width, s.cam.height, helpFrame}, "help_window");
  key(i, "h");
  EXPECT_FALSE(s.viewer->helpShown());
  std::string hud = s.viewer->hudText();
  for (const char* what : {"fps", "glossy update", "ms", "vertices updated", "glossy vertices"})
    EXPECT_NE(hud.find(what), std::string::npos) << hud;
  EXPECT_EQ(s.viewer->lastFrame().verticesUpdated, s.scene->glossyVertexCount()) << "threshold 0: all, every frame";
  key(i, "f");
  EXPECT_TRUE(s.viewer->walkMode());
  hr::Camera c0 = s.scene->camera(1, 1);
  key(i, "w");
  hr::Camera c1 = s.scene->camera(1, 1);
  EXPECT_NEAR(glm::length(c1.eye - c0.eye), 0.02 * s.scene->sceneRadius(), 1e-9);
  EXPECT_NEAR(c1.eye.y, c0.eye.y, 1e-12) << "walking keeps the eye's height";
  drag(i, 160, 120, 120, 120);
  hr::Camera c2 = s.scene->camera(1, 1);
  EXPECT_LT(glm::length(c2.eye - c1.eye), 1e-12) << "looking around keeps the eye";
  EXPECT_GT(glm::length(glm::normalize(c2.lookAt - c2.eye) - glm::normalize(c1.lookAt - c1.eye)), 0.05);
  key(i, "c");
  EXPECT_EQ(s.viewer->cameraIndex(), 1);
  EXPECT_LT(glm::length(s.scene->camera(1, 1).eye - second.eye), 1e-9);
  key(i, "c");
  EXPECT_EQ(s.viewer->cameraIndex(), 0);
}

}  // namespace
