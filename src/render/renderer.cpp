#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "core/names.h"
#include "geometry/export.h"
#include "model/device.h"
#include "render/gl.h"

namespace sscs {

namespace {

constexpr const char* kSolidVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model;
uniform mat4 view_projection;
uniform mat4 light_projection;   // world -> the shadow map's clip space
uniform mat3 normal_matrix;
out vec3 world_normal;
out vec4 light_position;
void main() {
  vec4 world = model * vec4(position, 1.0);
  world_normal = normal_matrix * normal;
  light_position = light_projection * world;
  gl_Position = view_projection * world;
}
)";

constexpr const char* kDepthVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 model;
uniform mat4 light_projection;
void main() { gl_Position = light_projection * model * vec4(position, 1.0); }
)";

constexpr const char* kDepthFragment = R"(#version 330 core
void main() {}
)";

// The id pass (Renderer::visibility): each object in a flat colour that encodes its index.
constexpr const char* kIdFragment = R"(#version 330 core
uniform vec3 id_color;
out vec4 color;
void main() { color = vec4(id_color, 1.0); }
)";

constexpr const char* kSolidFragment = R"(#version 330 core
in vec3 world_normal;
in vec4 light_position;
uniform vec3 albedo;      // linear light
uniform float alpha;      // 1 but for a see-through wall
uniform bool shadows;
uniform sampler2DShadow shadow_map;
out vec4 color;
const vec3 key_direction = normalize(vec3(-0.45, -0.6, -0.66));   // sunlight from above, behind the default eye
const vec3 sky = vec3(0.62, 0.68, 0.78);
const vec3 ground = vec3(0.30, 0.27, 0.24);
void main() {
  vec3 n = normalize(world_normal);
  if (!gl_FrontFacing) n = -n;
  float key = max(dot(n, -key_direction), 0.0);
  if (shadows && key > 0.0) {
    // 3x3 percentage-closer filtering of the shadow map, biased by the surface's slope.
    vec3 p = light_position.xyz / light_position.w * 0.5 + 0.5;
    float bias = 0.0015 + 0.003 * (1.0 - key);
    float lit = 0.0;
    vec2 texel = 1.0 / vec2(textureSize(shadow_map, 0));
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y) lit += texture(shadow_map, vec3(p.xy + vec2(x, y) * texel, p.z - bias));
    key *= p.z > 1.0 ? 1.0 : lit / 9.0;
  }
  vec3 ambient = mix(ground, sky, 0.5 + 0.5 * n.z);
  vec3 lit = albedo * (0.55 * ambient + 0.75 * key);
  color = vec4(pow(clamp(lit, 0.0, 1.0), vec3(1.0 / 2.2)), alpha);   // back to sRGB
}
)";

constexpr const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 line_color;
uniform mat4 view_projection;
out vec3 vertex_color;
void main() {
  vertex_color = line_color;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

constexpr const char* kLineFragment = R"(#version 330 core
in vec3 vertex_color;
out vec4 color;
void main() { color = vec4(vertex_color, 1.0); }
)";


Eigen::Matrix4f to_float(const Eigen::Matrix4d& M) { return M.cast<float>(); }

constexpr float kSeeThroughAlpha = 0.22f;  // a see-through wall's opacity: there, and what it hides seen

/// What may be drawn see-through: walls, and the doors and fences in the same planes (a rollup
/// door left solid in a see-through end wall hid the racks behind it), as the pages' switch does.
bool see_through_kind(const std::string& type) { return type == "wall" || type == "door" || type == "rollup_door" || type == "fence"; }

}  // namespace

/// A wall's plane: through the middle of its bounds, square to its thinnest horizontal side in
/// its own frame (a wall type's y, through it). Outside the anonymous namespace: Renderer::Impl
/// holds them, and g++ refuses such a field in a unity build (-Wsubobject-linkage).
struct WallPlane {
  int object = -1;
  Eigen::Vector3d middle, normal;
};

namespace {

std::vector<WallPlane> wall_planes(const Workcell& wc, const GeometryModel& geometry) {
  std::vector<WallPlane> out;
  for (size_t o = 0; o < wc.objects.size() && o < geometry.objects.size(); ++o) {
    const std::vector<int> lineage = wc.lineage(wc.objects[o].type);
    if (std::none_of(lineage.begin(), lineage.end(), [&](int t) { return see_through_kind(wc.types[t].name); })) continue;
    const ObjectGeometry& g = geometry.objects[o];
    if (g.shapes.empty() || g.bbox_world.isEmpty()) continue;
    Eigen::AlignedBox3d own;
    for (const Shape& sh : g.shapes) own.extend(shape_bounds(sh, sh.X_object_shape));
    const int thin = own.sizes().x() <= own.sizes().y() ? 0 : 1;
    out.push_back({static_cast<int>(o), g.bbox_world.center(), g.X_world_object.linear().col(thin).normalized()});
  }
  return out;
}

/// The planes of `walls` that separate `eye` from `middle`.
std::vector<int> separating(const std::vector<WallPlane>& walls, const Eigen::Vector3d& eye, const Eigen::Vector3d& middle) {
  std::vector<int> out;
  for (const WallPlane& w : walls)
    if (w.normal.dot(eye - w.middle) * w.normal.dot(middle - w.middle) < 0) out.push_back(w.object);
  return out;
}

}  // namespace

std::vector<int> see_through_walls(const Workcell& wc, const GeometryModel& geometry, const Eigen::Vector3d& eye,
                                   const Eigen::Vector3d& middle) {
  return separating(wall_planes(wc, geometry), eye, middle);
}

Eigen::Vector3f color_of(const std::string& hex) {
  const float grey = 0xC0 / 255.0f;  // #C0C0C0 for objects without a colour
  auto rgb = color_rgb(hex, {grey, grey, grey});
  return Eigen::Vector3f(rgb[0], rgb[1], rgb[2]).array().pow(2.2f);  // sRGB to linear light
}

struct Renderer::Impl {
  RenderOptions options;
  gl::Context context;
  const gl::Api& gl;
  const GeometryModel& geometry;
  struct Mesh {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
  };
  std::vector<Mesh> meshes;
  struct Item {
    int object = -1;
    int part = -1;                     ///< device part it hangs on, or -1: the object's frame
    Eigen::Isometry3d X_anchor_shape;  ///< the shape in its part's (or object's) frame
    size_t mesh = 0;
    Eigen::Vector3f albedo;
    bool inside = false;               ///< a container: drawn from the inside
  };
  std::vector<Item> items;
  std::vector<WallPlane> walls;  ///< see-through candidates (options.see_through)
  Mesh lines;
  GLuint solid = 0, line = 0, depth = 0;
  GLuint shadow_fbo = 0, shadow_map = 0;
  static constexpr int kShadowSize = 2048;
  GLuint fbo = 0, color_rb = 0, depth_rb = 0, resolve_fbo = 0, resolve_rb = 0;
  GLuint ids = 0, id_fbo = 0, id_color_rb = 0, id_depth_rb = 0;  // the id pass, made when first asked
  int id_w = 0, id_h = 0;
  Eigen::AlignedBox3d bounds;
  double draw_s = 0, readback_s = 0;

  Impl(const Workcell& wc, const GeometryModel& geometry_, const RenderOptions& o)
      : options(o), context(o.width, o.height), gl(context.api()), geometry(geometry_) {
    solid = program(kSolidVertex, kSolidFragment);
    line = program(kLineVertex, kLineFragment);
    framebuffers();
    if (options.shadows) shadow_buffers();
    upload(wc);
    if (options.see_through) walls = wall_planes(wc, geometry);
    grid();
  }

  ~Impl() {
    for (const Mesh& m : meshes) release(m);
    release(lines);
    gl.DeleteProgram(solid);
    gl.DeleteProgram(line);
    if (depth) gl.DeleteProgram(depth);
    if (ids) {
      gl.DeleteProgram(ids);
      GLuint id_rbs[] = {id_color_rb, id_depth_rb};
      gl.DeleteFramebuffers(1, &id_fbo);
      gl.DeleteRenderbuffers(2, id_rbs);
    }
    if (shadow_map) gl.DeleteTextures(1, &shadow_map);
    if (shadow_fbo) gl.DeleteFramebuffers(1, &shadow_fbo);
    GLuint fbos[] = {fbo, resolve_fbo}, rbs[] = {color_rb, depth_rb, resolve_rb};
    gl.DeleteFramebuffers(2, fbos);
    gl.DeleteRenderbuffers(3, rbs);
  }

  void release(const Mesh& m) {
    gl.DeleteBuffers(1, &m.vbo);
    gl.DeleteVertexArrays(1, &m.vao);
  }

  /// Throws with the info log when a shader's or program's status query says it failed.
  template <typename GetIv, typename GetLog>
  void require(GLuint object, GetIv get_iv, GetLog get_log, GLenum status, const char* what) {
    GLint ok = 0;
    get_iv(object, status, &ok);
    if (ok) return;
    char log[2048] = "";
    get_log(object, sizeof log, nullptr, log);
    throw std::runtime_error(fmt::format("{}: {}", what, log));
  }

  GLuint shader(GLenum kind, const char* source) {
    GLuint s = gl.CreateShader(kind);
    gl.ShaderSource(s, 1, &source, nullptr);
    gl.CompileShader(s);
    require(s, gl.GetShaderiv, gl.GetShaderInfoLog, GL_COMPILE_STATUS, "shader does not compile");
    return s;
  }

  GLuint program(const char* vertex, const char* fragment) {
    GLuint p = gl.CreateProgram();
    GLuint vs = shader(GL_VERTEX_SHADER, vertex), fs = shader(GL_FRAGMENT_SHADER, fragment);
    gl.AttachShader(p, vs);
    gl.AttachShader(p, fs);
    gl.LinkProgram(p);
    gl.DeleteShader(vs);
    gl.DeleteShader(fs);
    require(p, gl.GetProgramiv, gl.GetProgramInfoLog, GL_LINK_STATUS, "shader program does not link");
    return p;
  }

  /// A renderbuffer of `format` (`samples` 0: not multisampled) attached to the bound framebuffer.
  GLuint attach_renderbuffer(GLenum format, int w, int h, int samples, GLenum attachment) {
    GLuint rb = 0;
    gl.GenRenderbuffers(1, &rb);
    gl.BindRenderbuffer(GL_RENDERBUFFER, rb);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb);
    return rb;
  }

  void framebuffers() {
    const int w = options.width, h = options.height, n = std::max(1, options.samples);
    gl.GenFramebuffers(1, &fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    color_rb = attach_renderbuffer(GL_RGBA8, w, h, n, GL_COLOR_ATTACHMENT0);
    depth_rb = attach_renderbuffer(GL_DEPTH_COMPONENT24, w, h, n, GL_DEPTH_ATTACHMENT);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error(fmt::format("cannot make a {}x{} framebuffer with {} samples", w, h, n));
    gl.GenFramebuffers(1, &resolve_fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
    resolve_rb = attach_renderbuffer(GL_RGBA8, w, h, 0, GL_COLOR_ATTACHMENT0);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("cannot make the resolve framebuffer");
  }

  /// A depth texture the key light renders into; sampled with hardware depth comparison.
  void shadow_buffers() {
    depth = program(kDepthVertex, kDepthFragment);
    gl.GenTextures(1, &shadow_map);
    gl.BindTexture(GL_TEXTURE_2D, shadow_map);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, kShadowSize, kShadowSize, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    gl.GenFramebuffers(1, &shadow_fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_map, 0);
    gl.DrawBuffer(GL_NONE);
    gl.ReadBuffer(GL_NONE);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("cannot make the shadow map's framebuffer");
  }

  /// World -> the key light's clip space: an orthographic box around the scene's bounds.
  Eigen::Matrix4d light_projection() const {
    const Eigen::Vector3d dir = Eigen::Vector3d(-0.45, -0.6, -0.66).normalized();  // as in the shader
    const Eigen::Vector3d centre = bounds.isEmpty() ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(bounds.center());
    const double r = bounds.isEmpty() ? 10 : std::max(0.5 * bounds.diagonal().norm(), 1.0);
    Camera light{centre - dir * 2 * r, centre, 45};
    Eigen::Matrix4d P = Eigen::Matrix4d::Identity();
    P(0, 0) = P(1, 1) = 1 / r;
    P(2, 2) = -2 / (4 * r);  // depths 0 .. 4r from the light's eye (the scene lies within r .. 3r)
    P(2, 3) = -1;
    return P * view_matrix(light);
  }

  void draw_shadow_map(const ScenePose& pose, const Eigen::Matrix4f& light_vp) {
    gl.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    gl.Viewport(0, 0, kShadowSize, kShadowSize);
    gl.Clear(GL_DEPTH_BUFFER_BIT);
    gl.Enable(GL_DEPTH_TEST);
    gl.UseProgram(depth);
    gl.UniformMatrix4fv(gl.GetUniformLocation(depth, "light_projection"), 1, GL_FALSE, light_vp.data());
    const GLint u_model = gl.GetUniformLocation(depth, "model");
    for (const Item& it : items) {
      if (it.inside || pose.hides(it.object)) continue;  // rooms and containers do not shade what they hold
      const Eigen::Matrix4f model = to_float(world_pose(it, pose).matrix());
      gl.UniformMatrix4fv(u_model, 1, GL_FALSE, model.data());
      gl.BindVertexArray(meshes[it.mesh].vao);
      gl.DrawArrays(GL_TRIANGLES, 0, meshes[it.mesh].count);
    }
  }

  Eigen::Isometry3d world_pose(const Item& it, const ScenePose& pose) const {
    Eigen::Isometry3d X = pose.X_world_object[it.object];
    if (it.part >= 0) X = X * pose.X_object_part[it.object][it.part];
    return X * it.X_anchor_shape;
  }

  /// A vertex array of interleaved (position, normal or colour) floats.
  Mesh buffer(const std::vector<float>& data) {
    Mesh m;
    m.count = static_cast<GLsizei>(data.size() / 6);
    gl.GenVertexArrays(1, &m.vao);
    gl.BindVertexArray(m.vao);
    gl.GenBuffers(1, &m.vbo);
    gl.BindBuffer(GL_ARRAY_BUFFER, m.vbo);
    gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    gl.EnableVertexAttribArray(1);
    gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
    return m;
  }

  /// One vertex buffer per distinct shape (an array of 200 racks shares its meshes).
  void upload(const Workcell& wc) {
    std::map<std::string, size_t> known;
    const std::vector<char> container = containers(wc);
    for (size_t o = 0; o < geometry.objects.size(); ++o) {
      const ObjectGeometry& g = geometry.objects[o];
      bounds.extend(g.bbox_world);
      for (const Shape& s : g.drawn_shapes()) {
        Shape local = s;
        local.X_object_shape.setIdentity();
        auto [it, fresh] = known.try_emplace(shape_key(s), meshes.size());
        if (fresh) meshes.push_back(buffer(shaded_triangles(tessellate(local))));
        Item item;
        item.object = static_cast<int>(o);
        item.mesh = it->second;
        item.part = g.device ? s.part : -1;
        item.X_anchor_shape = item.part >= 0 ? g.X_object_part[item.part].inverse() * s.X_object_shape : s.X_object_shape;
        // The shape's own colour (a URDF visual's material), else its part's, else its object's.
        const std::string& part_color = item.part >= 0 ? g.device->parts[item.part].color : std::string();
        item.albedo = color_of(!s.color.empty() ? s.color : part_color.empty() ? wc.objects[o].color : part_color);
        item.inside = container[o];
        items.push_back(item);
      }
    }
  }

  /// The ground grid (1 m, or 10 m over large scenes) under the scene, and the world axes.
  void grid() {
    std::vector<float> v;
    auto add = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3f& c) {
      for (const Eigen::Vector3d* p : {&a, &b}) {
        for (int k = 0; k < 3; ++k) v.push_back(static_cast<float>((*p)[k]));
        for (int k = 0; k < 3; ++k) v.push_back(c[k]);
      }
    };
    Eigen::AlignedBox3d b = bounds.isEmpty() ? Eigen::AlignedBox3d(Eigen::Vector3d(-5, -5, 0), Eigen::Vector3d(5, 5, 0)) : bounds;
    const double z = std::min(0.0, b.min().z()) + 0.002;  // just above a floor at 0
    const double span = std::max(b.sizes().x(), b.sizes().y());
    const double step = span > 100 ? 10 : 1;
    const double x0 = std::floor(b.min().x() / step - 2) * step, x1 = std::ceil(b.max().x() / step + 2) * step;
    const double y0 = std::floor(b.min().y() / step - 2) * step, y1 = std::ceil(b.max().y() / step + 2) * step;
    const Eigen::Vector3f grey(0.55f, 0.55f, 0.55f);
    for (double x = x0; x <= x1 + 1e-9; x += step) add({x, y0, z}, {x, y1, z}, grey);
    for (double y = y0; y <= y1 + 1e-9; y += step) add({x0, y, z}, {x1, y, z}, grey);
    // The axes a little above the grid, so they win where they run along a grid line.
    const double axis = std::max(2.0, 2 * step), za = z + 0.005;
    add({0, 0, za}, {axis, 0, za}, {0.85f, 0.1f, 0.1f});
    add({0, 0, za}, {0, axis, za}, {0.1f, 0.7f, 0.1f});
    add({0, 0, za}, {0, 0, za + axis}, {0.1f, 0.2f, 0.9f});
    lines = buffer(v);
  }

  /// World -> clip space, the depth range from the scene's bounds as seen from the eye.
  Eigen::Matrix4f view_projection(const Camera& camera, double aspect) const {
    double far = 10;
    if (!bounds.isEmpty())
      for (int c = 0; c < 8; ++c)
        far = std::max(far, (bounds.corner(Eigen::AlignedBox3d::CornerType(c)) - camera.eye).norm());
    return to_float(projection_matrix(camera.fov, aspect, std::max(0.01, far * 1e-4), 2 * far + 100) * view_matrix(camera));
  }

  /// Pixels of each object of `objects` in an id image `width` wide (the frames' aspect): where it
  /// is in front with everything drawn, and where it is with only `objects` drawn.
  std::vector<Renderer::Visibility> visibility(const Camera& camera, const ScenePose& pose, const std::vector<int>& objects, int width) {
    const int w = std::max(8, width), h = std::max(8, static_cast<int>(std::lround(width * double(options.height) / options.width)));
    if (!ids) ids = program(kDepthVertex, kIdFragment);
    if (w != id_w || h != id_h) {
      if (id_fbo) {
        GLuint id_rbs[] = {id_color_rb, id_depth_rb};
        gl.DeleteFramebuffers(1, &id_fbo);
        gl.DeleteRenderbuffers(2, id_rbs);
      }
      gl.GenFramebuffers(1, &id_fbo);
      gl.BindFramebuffer(GL_FRAMEBUFFER, id_fbo);
      id_color_rb = attach_renderbuffer(GL_RGBA8, w, h, 0, GL_COLOR_ATTACHMENT0);
      id_depth_rb = attach_renderbuffer(GL_DEPTH_COMPONENT24, w, h, 0, GL_DEPTH_ATTACHMENT);
      if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error(fmt::format("cannot make a {}x{} id framebuffer", w, h));
      id_w = w;
      id_h = h;
    }
    std::vector<int> slot(geometry.objects.size(), -1);
    for (size_t k = 0; k < objects.size(); ++k) slot[objects[k]] = static_cast<int>(k);
    std::vector<Renderer::Visibility> out(objects.size());
    const Eigen::Matrix4f vp = view_projection(camera, double(w) / h);
    for (bool everything : {true, false}) {
      gl.BindFramebuffer(GL_FRAMEBUFFER, id_fbo);
      gl.Viewport(0, 0, w, h);
      gl.ClearColor(0, 0, 0, 1);
      gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      gl.Enable(GL_DEPTH_TEST);
      gl.UseProgram(ids);
      gl.UniformMatrix4fv(gl.GetUniformLocation(ids, "light_projection"), 1, GL_FALSE, vp.data());
      const GLint u_model = gl.GetUniformLocation(ids, "model"), u_id = gl.GetUniformLocation(ids, "id_color");
      // A see-through wall hides nothing from the camera.
      std::vector<char> through(geometry.objects.size(), 0);
      for (int o : separating(walls, camera.eye, bounds.center())) through[o] = 1;
      for (const Item& it : items) {
        if ((!everything && slot[it.object] < 0) || pose.hides(it.object) || (everything && through[it.object])) continue;
        const Eigen::Matrix4f model = to_float(world_pose(it, pose).matrix());
        gl.UniformMatrix4fv(u_model, 1, GL_FALSE, model.data());
        const int id = it.object + 1;  // 0: nothing
        gl.Uniform3f(u_id, (id & 255) / 255.0f, ((id >> 8) & 255) / 255.0f, ((id >> 16) & 255) / 255.0f);
        if (it.inside) {  // a room is seen from the inside, as in the frames
          gl.Enable(GL_CULL_FACE);
          gl.CullFace(GL_FRONT);
        } else {
          gl.Disable(GL_CULL_FACE);
        }
        gl.BindVertexArray(meshes[it.mesh].vao);
        gl.DrawArrays(GL_TRIANGLES, 0, meshes[it.mesh].count);
      }
      gl.Disable(GL_CULL_FACE);
      std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4);
      gl.BindFramebuffer(GL_READ_FRAMEBUFFER, id_fbo);
      gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
      gl.ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
      for (size_t p = 0; p < rgba.size(); p += 4) {
        const int id = rgba[p] | (rgba[p + 1] << 8) | (rgba[p + 2] << 16);
        if (id == 0 || id > static_cast<int>(slot.size()) || slot[id - 1] < 0) continue;
        (everything ? out[slot[id - 1]].visible : out[slot[id - 1]].alone)++;
      }
    }
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR) throw std::runtime_error(fmt::format("OpenGL error 0x{:x}", e));
    return out;
  }

  Image draw(const Camera& camera, const ScenePose& pose) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const int w = options.width, h = options.height;
    const Eigen::Matrix4f light_vp = to_float(light_projection());
    if (options.shadows) draw_shadow_map(pose, light_vp);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.Viewport(0, 0, w, h);
    gl.ClearColor(0.93f, 0.94f, 0.96f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.Enable(GL_DEPTH_TEST);
    if (options.samples > 1) gl.Enable(GL_MULTISAMPLE);

    const Eigen::Matrix4f vp = view_projection(camera, double(w) / h);

    gl.UseProgram(solid);
    const GLint u_model = gl.GetUniformLocation(solid, "model"), u_vp = gl.GetUniformLocation(solid, "view_projection"),
                u_normal = gl.GetUniformLocation(solid, "normal_matrix"), u_albedo = gl.GetUniformLocation(solid, "albedo"),
                u_alpha = gl.GetUniformLocation(solid, "alpha");
    gl.UniformMatrix4fv(u_vp, 1, GL_FALSE, vp.data());
    gl.Uniform1f(u_alpha, 1.0f);
    // The walls between the eye and the scene's middle: drawn last, see-through.
    std::vector<char> through(geometry.objects.size(), 0);
    bool any_through = false;
    for (int o : separating(walls, camera.eye, bounds.center())) through[o] = 1, any_through = true;
    gl.UniformMatrix4fv(gl.GetUniformLocation(solid, "light_projection"), 1, GL_FALSE, light_vp.data());
    gl.Uniform1i(gl.GetUniformLocation(solid, "shadows"), options.shadows ? 1 : 0);
    gl.Uniform1i(gl.GetUniformLocation(solid, "shadow_map"), 0);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, shadow_map);
    auto place = [&](const Item& it) {
      const Eigen::Isometry3d X = world_pose(it, pose);
      const Eigen::Matrix4f model = to_float(X.matrix());
      const Eigen::Matrix3f normal = X.linear().inverse().transpose().cast<float>();
      gl.UniformMatrix4fv(u_model, 1, GL_FALSE, model.data());
      gl.UniformMatrix3fv(u_normal, 1, GL_FALSE, normal.data());
      gl.Uniform3f(u_albedo, it.albedo.x(), it.albedo.y(), it.albedo.z());
    };
    for (const Item& it : items) {
      if (pose.hides(it.object) || through[it.object]) continue;
      place(it);
      // A container is seen from the inside: its faces towards the eye are not drawn, and its
      // far faces lie a little behind a solid's face in the same plane (a wall built against
      // the room's inside flickered in stripes with it).
      if (it.inside) {
        gl.Enable(GL_CULL_FACE);
        gl.CullFace(GL_FRONT);
        gl.Enable(GL_POLYGON_OFFSET_FILL);
        gl.PolygonOffset(2, 8);
      } else {
        gl.Disable(GL_CULL_FACE);
        gl.Disable(GL_POLYGON_OFFSET_FILL);
      }
      gl.BindVertexArray(meshes[it.mesh].vao);
      gl.DrawArrays(GL_TRIANGLES, 0, meshes[it.mesh].count);
    }
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    if (options.grid) {
      gl.UseProgram(line);
      gl.UniformMatrix4fv(gl.GetUniformLocation(line, "view_projection"), 1, GL_FALSE, vp.data());
      gl.BindVertexArray(lines.vao);
      gl.DrawArrays(GL_LINES, 0, lines.count);
    }
    if (any_through) {  // blended over everything, hiding nothing (no depth written)
      gl.UseProgram(solid);
      gl.Enable(GL_BLEND);
      gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
      gl.DepthMask(GL_FALSE);
      gl.Uniform1f(u_alpha, kSeeThroughAlpha);
      for (const Item& it : items) {
        if (pose.hides(it.object) || !through[it.object]) continue;
        place(it);
        gl.BindVertexArray(meshes[it.mesh].vao);
        gl.DrawArrays(GL_TRIANGLES, 0, meshes[it.mesh].count);
      }
      gl.Uniform1f(u_alpha, 1.0f);
      gl.DepthMask(GL_TRUE);
      gl.Disable(GL_BLEND);
    }

    gl.Finish();  // llvmpipe draws lazily: finish here, so the times split honestly
    const auto t1 = Clock::now();
    draw_s += std::chrono::duration<double>(t1 - t0).count();
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
    gl.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo);
    std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR) throw std::runtime_error(fmt::format("OpenGL error 0x{:x}", e));
    Image img{w, h, std::vector<uint8_t>(static_cast<size_t>(w) * h * 3)};
    for (int y = 0; y < h; ++y)  // OpenGL's rows start at the bottom
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) img.rgb[(static_cast<size_t>(y) * w + x) * 3 + c] = rgba[(static_cast<size_t>(h - 1 - y) * w + x) * 4 + c];
    readback_s += std::chrono::duration<double>(Clock::now() - t1).count();
    return img;
  }
};

Renderer::Renderer(const Workcell& wc, const GeometryModel& geometry, const RenderOptions& options)
    : impl_(std::make_unique<Impl>(wc, geometry, options)) {}
Renderer::~Renderer() = default;

Image Renderer::render(const Camera& camera, const ScenePose& pose) { return impl_->draw(camera, pose); }
Image Renderer::render(const Camera& camera) { return impl_->draw(camera, ScenePose::of(impl_->geometry)); }
std::vector<Renderer::Visibility> Renderer::visibility(const Camera& camera, const ScenePose& pose, const std::vector<int>& objects, int width) {
  return impl_->visibility(camera, pose, objects, width);
}
const Eigen::AlignedBox3d& Renderer::bounds() const { return impl_->bounds; }
std::string Renderer::gl_renderer() const { return impl_->context.renderer(); }
double Renderer::draw_seconds() const { return impl_->draw_s; }
double Renderer::readback_seconds() const { return impl_->readback_s; }

}  // namespace sscs
