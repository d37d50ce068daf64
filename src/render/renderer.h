#pragma once
/// The render stage: a workcell drawn offscreen (OSMesa, OpenGL 3.3 core) with shaders and
/// vertex buffers uploaded once per mesh: lit shading (a directional key light and a sky/ground
/// hemisphere), each object's or device part's colour, a ground grid and world axes, 4x MSAA.
/// Objects that hold others (rooms, containers) are drawn from the inside (their near walls
/// culled), so what they hold stays visible.
#include <memory>
#include <vector>

#include "compile/workcell.h"
#include "geometry/geometry.h"
#include "render/camera.h"
#include "render/image.h"

namespace sscs {

struct RenderOptions {
  int width = 1280, height = 720;
  bool grid = true;  ///< ground grid and world axes
  int samples = 4;   ///< MSAA samples (1: none)
  bool shadows = false;  ///< shadows of the key light (a 2048x2048 shadow map, 3x3 PCF)
  /// Walls towards the camera drawn see-through (a quarter opaque): those whose plane lies
  /// between the eye and the middle of the scene (see_through_walls()).
  bool see_through = false;
};

/// The walls (objects of type `wall`, `door`, `rollup_door` or `fence`, or a type extending one)
/// whose plane separates `eye` from `middle`: the walls a camera at `eye` looks through at the
/// scene. A wall's plane passes through the middle of its bounds, square to its thinnest
/// horizontal side.
std::vector<int> see_through_walls(const Workcell& wc, const GeometryModel& geometry, const Eigen::Vector3d& eye,
                                   const Eigen::Vector3d& middle);

class Renderer {
 public:
  /// Creates the context and uploads every mesh. Throws gl::RenderUnavailable (no OSMesa) or
  /// std::runtime_error (a shader or framebuffer problem).
  Renderer(const Workcell& wc, const GeometryModel& geometry, const RenderOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  Image render(const Camera& camera, const ScenePose& pose);
  Image render(const Camera& camera);  ///< at the geometry's own placement
  /// How much of an object the camera shows, in pixels of an id image (each object drawn in a
  /// flat colour of its own, `width` pixels wide at the frames' aspect): where it is in front
  /// with the whole scene drawn, and where it would be with only the objects asked about.
  struct Visibility {
    int visible = 0, alone = 0;
    double fraction() const { return alone > 0 ? double(visible) / alone : 0.0; }
  };
  std::vector<Visibility> visibility(const Camera& camera, const ScenePose& pose, const std::vector<int>& objects, int width = 192);
  /// The scene's world bounds (for framing cameras).
  const Eigen::AlignedBox3d& bounds() const;
  std::string gl_renderer() const;
  /// Seconds spent so far drawing (until the GPU has finished) and reading pixels back.
  double draw_seconds() const;
  double readback_seconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// "#RRGGBB" -> linear-light RGB in [0, 1] (sRGB decoded); grey for "".
Eigen::Vector3f color_of(const std::string& hex);

}  // namespace sscs
