// Offscreen rendering against camera geometry: where a box lands on the image, and that the
// same scene renders to the same pixels twice.
#include <algorithm>

#include "render/camera.h"
#include "render/camera_path.h"
#include "render/contact_sheet.h"
#include "render/text.h"
#include "render/renderer.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using Render = VaultTest;

const std::vector<std::pair<std::string, std::string>> kCube = {
    {"cube", "sscs: 1\ntype: cube\ncolor: \"#FF0000\"\nattributes:\n  side: {type: length, default: 1}\n"
             "geometry:\n  - box: {size: [side, side, side], xyz: [0, 0, \"side/2\"]}\n"}};

struct Scene {
  Workcell wc;
  GeometryModel geometry;
};

Scene scene(VaultTest& t, const std::string& objects) {
  t.options.library_dirs = {t.type_dir(kCube)};
  Scene s{t.must_compile("objects:\n" + objects), {}};
  s.geometry = build_geometry(s.wc, t.diag);
  return s;
}

/// Bounds (x0, y0, x1, y1) of the pixels that are clearly red.
Eigen::Vector4d red_bounds(const Image& img) {
  Eigen::Vector4d b(1e9, 1e9, -1e9, -1e9);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* p = img.pixel(x, y);
      if (p[0] > 100 && p[1] < 60 && p[2] < 60) b = Eigen::Vector4d(std::min(b[0], double(x)), std::min(b[1], double(y)),
                                                                     std::max(b[2], double(x + 1)), std::max(b[3], double(y + 1)));
    }
  return b;
}

TEST(Camera, TargetProjectsToTheImageCentreAndUpIsUp) {
  Camera c{{10, -10, 8}, {1, 2, 3}, 50};
  Eigen::Vector2d centre = project_to_pixel(c, 640, 480, c.target);
  EXPECT_NEAR(centre.x(), 320, 1e-9);
  EXPECT_NEAR(centre.y(), 240, 1e-9);
  // A point above the target is higher on the image (smaller y).
  EXPECT_LT(project_to_pixel(c, 640, 480, c.target + Eigen::Vector3d(0, 0, 1)).y(), 240);
  // fov: a point at the top edge of the view, by hand: the ray at fov/2 above the axis.
  Camera level{{0, -10, 0}, {0, 0, 0}, 90};
  EXPECT_NEAR(project_to_pixel(level, 640, 480, {0, 0, 10}).y(), 0, 1e-9);  // tan(45) * 10 m at 10 m
}

TEST(Camera, FramingKeepsEveryCornerInView) {
  Eigen::AlignedBox3d box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(40, 10, 6));
  Camera c = framing_camera(box, 45, 16.0 / 9);
  for (int k = 0; k < 8; ++k) {
    Eigen::Vector2d p = project_to_pixel(c, 1280, 720, box.corner(Eigen::AlignedBox3d::CornerType(k)));
    EXPECT_GE(p.x(), 0);
    EXPECT_LE(p.x(), 1280);
    EXPECT_GE(p.y(), 0);
    EXPECT_LE(p.y(), 720);
  }
}

TEST(CameraPath, EasedLinesAndOrbitSweepsAgainstHandValues) {
  CameraKey a, b, c, d;
  a.t = 0, a.eye = {10, 0, 0}, a.target = {0, 0, 0}, a.fov = 40;
  b.t = 2, b.eye = {0, 10, 4}, b.target = {0, 0, 2}, b.fov = 60;
  c.t = 4, c.orbit = true, c.orbit_point = {1, 1, 0}, c.radius = 5, c.azimuth = 0, c.elevation = 0;
  d.t = 8, d.orbit = true, d.orbit_point = {1, 1, 0}, d.radius = 5, d.azimuth = M_PI, d.elevation = 0, d.fov = 45;
  CameraPath path({a, b, c, d});
  ScenePose none;
  Eigen::AlignedBox3d box;
  // Halfway between a and b: smoothstep(0.5) = 0.5, the midpoint.
  Camera m = path.at(1, none, box, 1.5);
  EXPECT_TRUE(m.eye.isApprox(Eigen::Vector3d(5, 5, 2)));
  EXPECT_TRUE(m.target.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_NEAR(m.fov, 50, 1e-12);
  // A quarter of the way: smoothstep(0.25) = 0.15625.
  EXPECT_TRUE(path.at(0.5, none, box, 1.5).eye.isApprox(Eigen::Vector3d(10 - 10 * 0.15625, 10 * 0.15625, 4 * 0.15625)));
  // Orbit to orbit about the same point: the azimuth sweeps, the radius stays 5 (not a chord).
  Camera q = path.at(6, none, box, 1.5);  // halfway: azimuth pi/2
  EXPECT_TRUE(q.eye.isApprox(Eigen::Vector3d(1, 6, 0), 1e-12));
  EXPECT_TRUE(q.target.isApprox(Eigen::Vector3d(1, 1, 0)));
  EXPECT_NEAR((path.at(5, none, box, 1.5).eye - Eigen::Vector3d(1, 1, 0)).norm(), 5, 1e-12);
  // Holds before the first key and after the last.
  EXPECT_TRUE(path.at(-1, none, box, 1.5).eye.isApprox(a.eye));
  EXPECT_TRUE(path.at(99, none, box, 1.5).eye.isApprox(Eigen::Vector3d(-4, 1, 0), 1e-12));
  EXPECT_NEAR(path.at(99, none, box, 1.5).fov, 45, 1e-12);
}

TEST(CameraPath, OrbitFollowsItsObject) {
  CameraKey k;
  k.orbit = true, k.orbit_object = 0, k.radius = 2, k.azimuth = M_PI / 2, k.elevation = 0;
  CameraPath path({k});
  ScenePose pose;
  pose.X_world_object = {Eigen::Isometry3d(Eigen::Translation3d(3, 4, 1))};
  Camera c = path.at(0, pose, {}, 1);
  EXPECT_TRUE(c.target.isApprox(Eigen::Vector3d(3, 4, 1)));
  EXPECT_TRUE(c.eye.isApprox(Eigen::Vector3d(3, 6, 1), 1e-12));
}

TEST_F(Render, BoxLandsOnThePixelsTheCameraPredicts) {
  Scene s = scene(*this, "  - {type: cube, name: A, location: [1, 2, 0], side: 1.5}\n");
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.grid = false;
  Renderer r(s.wc, s.geometry, o);
  Camera cam{{6, -4, 5}, {1.5, 2.5, 0.5}, 40};
  Image img = r.render(cam);
  // The cube's eight corners through the same camera matrices.
  Eigen::Vector4d expect(1e9, 1e9, -1e9, -1e9);
  for (int k = 0; k < 8; ++k) {
    // Centred on its location in x and y, standing on it.
    Eigen::Vector3d corner(1 + 1.5 * ((k & 1) - 0.5), 2 + 1.5 * (((k >> 1) & 1) - 0.5), 1.5 * ((k >> 2) & 1));
    Eigen::Vector2d p = project_to_pixel(cam, o.width, o.height, corner);
    expect = Eigen::Vector4d(std::min(expect[0], p.x()), std::min(expect[1], p.y()), std::max(expect[2], p.x()),
                             std::max(expect[3], p.y()));
  }
  Eigen::Vector4d got = red_bounds(img);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], expect[k], 2.0) << "edge " << k;
  EXPECT_GT(expect[2] - expect[0], 40);  // a box of a good size, not a few pixels
}

TEST_F(Render, SameSceneSamePixelsAndPosesMoveObjects) {
  Scene s = scene(*this, "  - {type: cube, name: A}\n  - {type: cube, name: B, location: [3, 0, 0]}\n");
  RenderOptions o;
  o.width = 200;
  o.height = 150;
  Renderer r(s.wc, s.geometry, o);
  Camera cam = framing_camera(r.bounds(), 45, 200.0 / 150);
  Image a = r.render(cam), b = r.render(cam);
  EXPECT_EQ(a.rgb, b.rgb);
  ScenePose moved = ScenePose::of(s.geometry);
  moved.X_world_object[1].translation().z() += 0.5;
  EXPECT_NE(r.render(cam, moved).rgb, a.rgb);
  // PNG round trip.
  Image back = decode_png(encode_png(a));
  EXPECT_EQ(back.width, a.width);
  EXPECT_EQ(back.rgb, a.rgb);
}

// See-through walls: a wall between the eye and the scene's middle hides a red cube when solid and
// shows it see-through; seen from the other side the wall stands behind the cube, is no
// see-through wall, and hides nothing. The same with the wall turned 90 degrees, seen along x.
TEST_F(Render, AWallBetweenTheEyeAndTheVaultIsSeeThrough) {
  for (int turned = 0; turned < 2; ++turned) {
    SCOPED_TRACE(turned ? "wall along y" : "wall along x");
    diag = Diagnostics{};
    // The wall: 4 m long, 0.2 m thick, 3 m high, 1 m from the cube (standing at the origin).
    Scene s = scene(*this, turned ? "  - {type: cube, name: A}\n  - {type: wall, name: W, location: [-1, -2, 0], orientation: [0, 0, 90], "
                                    "length: 4 m, thickness: 0.2 m, height: 3 m}\n"
                                  : "  - {type: cube, name: A}\n  - {type: wall, name: W, location: [-2, -1.2, 0], length: 4 m, "
                                    "thickness: 0.2 m, height: 3 m}\n");
    ASSERT_FALSE(diag.has_errors());
    const Eigen::Vector3d near = turned ? Eigen::Vector3d(-8, 0, 1.5) : Eigen::Vector3d(0, -8, 1.5);
    const Eigen::Vector3d middle(0, 0, 0.5);
    EXPECT_EQ(see_through_walls(s.wc, s.geometry, near, middle), std::vector<int>{1});
    EXPECT_TRUE(see_through_walls(s.wc, s.geometry, -near + Eigen::Vector3d(0, 0, 3), middle).empty());  // beyond the cube
    for (int see : {0, 1}) {
      RenderOptions o;
      o.width = 240;
      o.height = 180;
      o.grid = false;
      o.see_through = see;
      Renderer r(s.wc, s.geometry, o);
      const Eigen::Vector4d hidden = red_bounds(r.render(Camera{near, middle, 40}));
      if (see) {
        EXPECT_LT(hidden[0], hidden[2]) << "the cube is seen through the wall";
      } else {
        EXPECT_GT(hidden[0], hidden[2]) << "the solid wall hides the cube";
      }
      // From the far side the cube stands in front of the wall, see-through or not.
      const Eigen::Vector4d front = red_bounds(r.render(Camera{Eigen::Vector3d(-near.x(), -near.y(), near.z()), middle, 40}));
      EXPECT_LT(front[0], front[2]);
    }
  }
}

TEST(ContactSheet, DownscaleAveragesAndLabelsAreInked) {
  Image img{4, 2, std::vector<uint8_t>(4 * 2 * 3, 0)};
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      for (int k = 0; k < 3; ++k) img.rgb[(y * 4 + x) * 3 + k] = 200;  // left half light
  Image half = downscale(img, 2);
  ASSERT_EQ(half.width, 2);
  ASSERT_EQ(half.height, 1);
  EXPECT_EQ(half.pixel(0, 0)[0], 200);
  EXPECT_EQ(half.pixel(1, 0)[0], 0);
  Font font(default_font_path(), 20);
  EXPECT_GT(font.width("step 1"), font.width("1"));
  Image canvas{200, 40, std::vector<uint8_t>(200 * 40 * 3, 255)};
  const uint8_t ink[3] = {0, 0, 0};
  font.draw(canvas, 5, 30, "Hello", ink);
  int dark = 0, x_max = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 200; ++x)
      if (canvas.pixel(x, y)[0] < 128) ++dark, x_max = std::max(x_max, x);
  EXPECT_GT(dark, 40);
  EXPECT_LE(x_max, 5 + font.width("Hello"));  // the ink stays within the advance
  EXPECT_THROW(Font("/nonexistent.ttf", 12), std::runtime_error);
}

}  // namespace
}  // namespace sscs::testing
