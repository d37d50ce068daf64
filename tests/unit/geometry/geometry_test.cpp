#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>

#include "geometry/geometry.h"
#include "vault_fixture.h"
#include "core/units.h"

namespace sscs::testing {
namespace {

using Geometry = VaultTest;

TEST(GeometryMath, RpyIsZYXAsInUrdf) {
  // yaw 90 deg maps +x to +y; pitch 90 deg maps +x to -z; roll 90 deg maps +y to +z.
  EXPECT_TRUE((rpy_to_rotation(0, 0, kPi / 2) * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE((rpy_to_rotation(0, kPi / 2, 0) * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE((rpy_to_rotation(kPi / 2, 0, 0) * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ()));
  // R = Rz(yaw) Ry(pitch) Rx(roll): roll applies first.
  Eigen::Matrix3d R = rpy_to_rotation(0.1, 0.2, 0.3);
  Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX())).toRotationMatrix();
  EXPECT_TRUE(R.isApprox(expected));
}

TEST(GeometryMath, BoundsOfRotatedShapes) {
  Shape box;
  box.kind = Shape::Kind::Box;
  box.box_size = {2, 1, 1};
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = rpy_to_rotation(0, 0, kPi / 4);
  Eigen::AlignedBox3d b = shape_bounds(box, X);
  double half = (2 + 1) / 2.0 / std::sqrt(2.0);  // |R| * (1, 0.5, 0.5)
  EXPECT_NEAR(b.max().x(), half, 1e-12);
  EXPECT_NEAR(b.max().y(), half, 1e-12);
  EXPECT_NEAR(b.max().z(), 0.5, 1e-12);

  Shape cyl;
  cyl.kind = Shape::Kind::Cylinder;
  cyl.radius = 0.5;
  cyl.length = 2;
  X.linear() = rpy_to_rotation(0, kPi / 2, 0);  // axis along world x
  b = shape_bounds(cyl, X);
  EXPECT_NEAR(b.max().x(), 1.0, 1e-12);
  EXPECT_NEAR(b.max().y(), 0.5, 1e-12);
  EXPECT_NEAR(b.max().z(), 0.5, 1e-12);
}

TEST_F(Geometry, ParentChainsComposeWorldPoses) {
  Workcell wc = must_compile(
      "objects:\n"
      "  - {type: pallet, name: C, parent: B, location: [0, 1, 0]}\n"  // before its parent in the file
      "  - {type: room, name: A, length: 10, width: 10, height: 3, location: [5, 0, 0], orientation: [0, 0, 90]}\n"
      "  - {type: pallet, name: B, parent: A, location: [1, 0, 0.5], orientation: [0, 0, 90]}\n");
  GeometryModel g = build_geometry(wc, diag);
  ASSERT_FALSE(diag.has_errors());
  // A at (5,0,0) yawed 90; B at A-local (1,0,0.5) -> world (5,1,0.5), yawed 180; C at B-local (0,1,0) -> world (5,0,0.5).
  Eigen::Vector3d c = g.objects[wc.find_object("C")].X_world_object.translation();
  EXPECT_TRUE(c.isApprox(Eigen::Vector3d(5, 0, 0.5), 1e-12)) << c.transpose();
  // The pallet box of C (1.2 x 0.8, yawed 180 deg) spans x 5-1.2..5, y -0.8..0.
  const Eigen::AlignedBox3d& b = g.objects[wc.find_object("C")].bbox_world;
  // (The pallet is a mesh read through assimp in single precision.)
  EXPECT_NEAR(b.min().x(), 3.8, 1e-6);
  EXPECT_NEAR(b.max().y(), 0.0, 1e-6);
  EXPECT_NEAR(b.max().z(), 0.5 + 0.144, 1e-6);
}

TEST_F(Geometry, ShapeValuesFollowAttributes) {
  Workcell wc = must_compile("objects:\n  - {type: drum, name: D, diameter: 1 m, height: 2 m}\n");
  GeometryModel g = build_geometry(wc, diag);
  const ObjectGeometry& d = g.objects[0];
  ASSERT_EQ(d.shapes.size(), 1u);
  EXPECT_EQ(d.shapes[0].kind, Shape::Kind::Cylinder);
  EXPECT_DOUBLE_EQ(d.shapes[0].radius, 0.5);
  EXPECT_DOUBLE_EQ(d.shapes[0].length, 2.0);
  EXPECT_NEAR(d.bbox_world.max().z(), 2.0, 1e-12);
}

TEST_F(Geometry, MeshesLoadThroughAssimp) {
  std::string dir = type_dir({{"wedge", "sscs: 1\ntype: wedge\ngeometry:\n  - mesh: {file: wedge.obj, scale: [2, 1, 1]}\n"}});
  std::ofstream(std::filesystem::path(dir) / "wedge.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
  options.library_dirs = {dir};
  Workcell wc = must_compile("objects:\n  - {type: wedge, name: W, location: [1, 0, 0]}\n");
  GeometryModel g = build_geometry(wc, diag);
  ASSERT_FALSE(diag.has_errors()) << diag.format(sources);
  ASSERT_EQ(g.objects[0].shapes.size(), 1u);
  EXPECT_EQ(g.objects[0].shapes[0].mesh->triangles.size(), 4u);
  EXPECT_NEAR(g.objects[0].bbox_world.max().x(), 3.0, 1e-12);  // 1 + 2 * 1
}

TEST_F(Geometry, CorruptMeshIsAnInputError) {
  std::string dir = type_dir({{"blob", "sscs: 1\ntype: blob\ngeometry:\n  - mesh: {file: blob.stl}\n"}});
  std::ofstream(std::filesystem::path(dir) / "blob.stl") << "solid x\nthis is not an stl\n";
  options.library_dirs = {dir};
  Workcell wc = must_compile("objects:\n  - {type: blob, name: B}\n");
  build_geometry(wc, diag);
  ASSERT_TRUE(diag.has_errors());
  EXPECT_EQ(diag.errors()[0].mark.line, 4u);  // the line of the type file that names the mesh
}

}  // namespace
}  // namespace sscs::testing

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "geometry/export.h"
#include "render/gltf.h"
#include "geometry/mesh_io.h"

namespace sscs::testing {
namespace {

/// World bounds of every mesh under each named node (its own and its descendants'), as a viewer
/// would place them; `y_up` (glTF) turns the file's y up back into sscs's z up.
void collect(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, std::vector<std::string> names,
             std::map<std::string, Eigen::AlignedBox3d>& boxes, Eigen::AlignedBox3d& all, bool y_up) {
  aiMatrix4x4 world = parent * node->mTransformation;
  names.push_back(node->mName.C_Str());
  for (unsigned m = 0; m < node->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      aiVector3D p = world * mesh->mVertices[v];
      const Eigen::Vector3d x = y_up ? Eigen::Vector3d(p.x, -p.z, p.y) : Eigen::Vector3d(p.x, p.y, p.z);
      for (const std::string& name : names) boxes[name].extend(x);
      all.extend(x);
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(scene, node->mChildren[c], world, names, boxes, all, y_up);
}

TEST_F(Geometry, ExportRoundTripKeepsNamesAndBounds) {
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: Room1, length: 6, width: 4, height: 3, location: [1, 2, 0], orientation: [0, 0, 30]}\n"
      "  - {type: drum, name: Drum1, parent: Room1, location: [1, 1, 0]}\n"
      "  - {type: rack, name: Rack1, parent: Room1, location: [3, 1, 0], orientation: [0, 0, 90]}\n");
  GeometryModel g = build_geometry(wc, diag);
  Eigen::AlignedBox3d expected;
  for (const ObjectGeometry& o : g.objects) expected.extend(o.bbox_world);
  auto dir = std::filesystem::temp_directory_path() / "sscs_export_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* ext : {"glb", "gltf", "obj", "stl"}) {
    std::string path = (dir / (std::string("w.") + ext)).string();
    ASSERT_EQ(write_export(wc, g, {}, path), "") << ext;
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    ASSERT_TRUE(scene) << ext << ": " << importer.GetErrorString();
    std::map<std::string, Eigen::AlignedBox3d> boxes;
    Eigen::AlignedBox3d all;
    collect(scene, scene->mRootNode, aiMatrix4x4(), {}, boxes, all, std::string(ext) == "glb" || std::string(ext) == "gltf");
    // The cylinder is tessellated with 32 segments: its bounds are exact along its own axes.
    EXPECT_TRUE(all.min().isApprox(expected.min(), 1e-4)) << ext << " " << all.min().transpose();
    EXPECT_TRUE(all.max().isApprox(expected.max(), 1e-4)) << ext << " " << all.max().transpose();
    if (std::string(ext) == "stl") continue;  // STL has no nodes
    if (std::string(ext) == "gltf") {
      EXPECT_FALSE(std::filesystem::exists(dir / "w.bin"));  // one file: its buffer inline
    }
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      EXPECT_NE(entry.path().filename().string()[0], '.') << "temporary left behind: " << entry.path();
    for (size_t i = 0; i < wc.objects.size(); ++i) {
      ASSERT_TRUE(boxes.count(wc.objects[i].name)) << ext << " lacks node " << wc.objects[i].name;
      const Eigen::AlignedBox3d& b = boxes[wc.objects[i].name];
      EXPECT_LT((b.min() - g.objects[i].bbox_world.min()).norm(), 0.02) << ext << " " << wc.objects[i].name;
      EXPECT_LT((b.max() - g.objects[i].bbox_world.max()).norm(), 0.02) << ext << " " << wc.objects[i].name;
    }
  }
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

TEST_F(Geometry, MeshFormatsLoadAlike) {
  // One tetrahedron in every format the library documents: OBJ and PLY written here, STL, glTF
  // and GLB written by our exporter from the OBJ.
  std::string dir = type_dir({});
  auto at = [&](const std::string& f) { return (std::filesystem::path(dir) / f).string(); };
  std::ofstream(at("t.obj")) << "v 0 0 0\nv 1 0 0\nv 0 2 0\nv 0 0 3\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  std::ofstream(at("t.ply")) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
                                "0 0 0\n1 0 0\n0 2 0\n0 0 3\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  MeshCache cache;
  auto obj = cache.load(at("t.obj"), {}, diag);
  ASSERT_TRUE(obj);
  Workcell wc;
  wc.name = "T";
  wc.types.emplace_back().name = "tetrahedron";
  wc.objects.push_back(Object{"Tet", 0, -1, 0, {}, "", "", ""});
  GeometryModel g;
  g.objects.resize(1);
  Shape s;
  s.kind = Shape::Kind::Mesh;
  s.mesh = obj;
  g.objects[0].shapes.push_back(s);
  for (const char* ext : {"stl", "gltf", "glb"}) ASSERT_EQ(write_export(wc, g, {}, at(std::string("t.") + ext)), "");
  for (const char* ext : {"obj", "ply", "stl", "gltf", "glb"}) {
    auto mesh = cache.load(at(std::string("t.") + ext), {}, diag);
    ASSERT_TRUE(mesh) << ext << diag.format(sources);
    EXPECT_EQ(mesh->triangles.size(), 4u) << ext;
    Eigen::AlignedBox3d b;
    for (const auto& v : mesh->vertices) b.extend(v);
    EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(1, 2, 3), 1e-6)) << ext << " " << b.max().transpose();
  }
  // Formats without materials give no colours (assimp's default material is none).
  EXPECT_TRUE(obj->triangle_rgb.empty());
}

TEST_F(Geometry, ColladaMeshesKeepTheirUpAxisAndMaterialColours) {
  // A vendor's visual mesh (Z_UP, as ROS packages write them; assimp turns it to Y up): the upper
  // arm stands along z, 0.6 m, its sides orange and its end caps dark, as the file says.
  MeshCache cache;
  auto mesh = cache.load(std::string(SSCS_TEST_DATA) + "/vendor/acme_rx6_support/meshes/visual/link_2.dae", {}, diag);
  ASSERT_TRUE(mesh) << diag.format(sources);
  Eigen::AlignedBox3d b;
  for (const auto& v : mesh->vertices) b.extend(v);
  EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(-0.05, -0.05, 0), 1e-9)) << b.min().transpose();
  EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(0.05, 0.05, 0.6), 1e-9)) << b.max().transpose();
  ASSERT_EQ(mesh->triangles.size(), 12u);
  ASSERT_EQ(mesh->triangle_rgb.size(), 12u);
  EXPECT_EQ(std::count(mesh->triangle_rgb.begin(), mesh->triangle_rgb.end(), 0x1f57800u), 8);
  EXPECT_EQ(std::count(mesh->triangle_rgb.begin(), mesh->triangle_rgb.end(), 0x11a1a1au), 4);
  EXPECT_TRUE(mesh->closed);
}

TEST_F(Geometry, TexturedMeshesTakeTheirColoursFromTheImage) {
  // A Collada file whose material is an image beside it (link_3.png: yellow left half, dark right
  // half): the sides sample the yellow half, the end caps the dark half.
  MeshCache cache;
  auto mesh = cache.load(std::string(SSCS_TEST_DATA) + "/vendor/acme_rx6_support/meshes/visual/link_3.dae", {}, diag);
  ASSERT_TRUE(mesh) << diag.format(sources);
  EXPECT_EQ(diag.format(sources), "");
  ASSERT_EQ(mesh->triangle_rgb.size(), 12u);
  EXPECT_EQ(std::count(mesh->triangle_rgb.begin(), mesh->triangle_rgb.end(), 0x1ffcc00u), 8);
  EXPECT_EQ(std::count(mesh->triangle_rgb.begin(), mesh->triangle_rgb.end(), 0x1222222u), 4);
  // A glTF whose base colour is a JPEG embedded in the file (a data URI): one triangle on the red
  // half, one on the blue (JPEG's loss rounded away to 4 bits a channel).
  auto gltf = cache.load(std::string(SSCS_TEST_DATA) + "/urdf/embedded_texture.gltf", {}, diag);
  ASSERT_TRUE(gltf) << diag.format(sources);
  ASSERT_EQ(gltf->triangle_rgb.size(), 2u);
  EXPECT_EQ(gltf->triangle_rgb[0], 0x1dd0000u) << std::hex << gltf->triangle_rgb[0];
  EXPECT_EQ(gltf->triangle_rgb[1], 0x10000ddu) << std::hex << gltf->triangle_rgb[1];
}

TEST_F(Geometry, AMissingOrBrokenTextureLeavesItsTrianglesUncolouredWithAWarning) {
  // Uncoloured, they take the URDF material's colour (else the part's): the textured material's
  // own diffuse colour is the loader's default grey, which drew a yellow robot grey.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / fmt::format("sscs-texture-{}", ::getpid());
  fs::create_directories(dir);
  std::string dae;
  {
    std::ifstream in(std::string(SSCS_TEST_DATA) + "/vendor/acme_rx6_support/meshes/visual/link_3.dae");
    dae.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(dir / "wrist.dae") << dae;
  MeshCache missing;
  auto mesh = missing.load((dir / "wrist.dae").string(), {}, diag);
  ASSERT_TRUE(mesh) << diag.format(sources);
  EXPECT_THAT(diag.format(sources), ::testing::HasSubstr("link_3.png' cannot be used (it does not exist): drawn without it"));
  EXPECT_FALSE(diag.has_errors());
  EXPECT_TRUE(mesh->triangle_rgb.empty());  // sides and caps alike: their colours were the texture's
  std::ofstream(dir / "link_3.png") << "GIF89a not an image";
  Diagnostics broken;
  MeshCache cache;
  mesh = cache.load((dir / "wrist.dae").string(), {}, broken);
  ASSERT_TRUE(mesh);
  EXPECT_THAT(broken.format(sources), ::testing::HasSubstr("(it is neither a PNG nor a JPEG image, the two sscs reads)"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sscs::testing

namespace sscs::testing {
namespace {

TEST_F(Geometry, NamedFramesFollowAttributesAndInheritance) {
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: R, length: 10, width: 10, height: 4, location: [10, 0, 0], orientation: [0, 0, 90]}\n"
      "  - {type: drum_hooped, name: D, parent: R, location: [1, 2, 0], height: 1 m}\n"
      "  - {type: rack, name: K, parent: R, location: [3, 3, 0], level_pitch: 2 m}\n");
  GeometryModel g = build_geometry(wc, diag);
  const Eigen::Isometry3d* top = g.objects[1].frame("top");  // inherited from drum
  ASSERT_TRUE(top);
  EXPECT_TRUE(top->translation().isApprox(Eigen::Vector3d(10 - 2, 1, 1), 1e-12)) << top->translation().transpose();
  const Eigen::Isometry3d* slot = g.objects[2].frame("slot_2");
  ASSERT_TRUE(slot);
  EXPECT_NEAR(slot->translation().z(), 0.15 + 2, 1e-12);
  EXPECT_FALSE(g.objects[2].frame("slot_9"));
}

// `repeat:` copies a geometry entry or frame over its counters, each from 1 to its count: the
// counters name values in the entry, the pitch moves copy k by (k - 1) pitches.
constexpr const char* kGrid =
    "sscs: 1\ntype: grid\nattributes:\n"
    "  rows: {type: integer, default: 2, min: 0}\n"
    "  cols: {type: integer, default: 3, min: 0}\n"
    "  pitch: {type: length, default: 1}\n"
    "  scale: {type: number, default: 1}\n"
    "frames:\n"
    "  cell_{row}_{col}: {xyz: [\"col * pitch\", 0, \"row\"], repeat: {row: rows, col: cols}}\n"
    "geometry:\n"
    "  - box: {size: [0.5, 0.5, \"0.1 * row\"], xyz: [0, 0, \"row * 10\"], repeat: {row: rows, col: {count: \"cols * scale\", pitch: [pitch, 0, 0]}}}\n"
    "  - sphere: {radius: 0.2, xyz: [0, 5, 0]}\n";

TEST_F(Geometry, RepeatedShapesAndFramesFollowTheirCounters) {
  options.library_dirs.push_back(type_dir({{"grid", kGrid}}));
  Workcell wc = must_compile("objects:\n  - {type: grid, name: G, location: [100, 0, 0]}\n  - {type: grid, name: H, rows: 3, cols: 1, pitch: 2}\n");
  GeometryModel g = build_geometry(wc, diag);
  ASSERT_EQ(g.objects[0].shapes.size(), 2u * 3u + 1u);
  // Row outermost: row 1's three columns, then row 2's; the sphere after them.
  for (int row = 1; row <= 2; ++row)
    for (int col = 1; col <= 3; ++col) {
      const Shape& s = g.objects[0].shapes[(row - 1) * 3 + (col - 1)];
      EXPECT_EQ(s.kind, Shape::Kind::Box);
      EXPECT_NEAR(s.box_size.z(), 0.1 * row, 1e-12);
      EXPECT_TRUE(s.X_object_shape.translation().isApprox(Eigen::Vector3d(col - 1, 0, row * 10), 1e-12))
          << row << " " << col << ": " << s.X_object_shape.translation().transpose();
    }
  EXPECT_EQ(g.objects[0].shapes.back().kind, Shape::Kind::Sphere);
  ASSERT_EQ(g.objects[1].shapes.size(), 3u + 1u);
  for (int row = 1; row <= 2; ++row)
    for (int col = 1; col <= 3; ++col) {
      const Eigen::Isometry3d* X = g.objects[0].frame(fmt::format("cell_{}_{}", row, col));
      ASSERT_TRUE(X) << row << " " << col;
      EXPECT_TRUE(X->translation().isApprox(Eigen::Vector3d(100 + col, 0, row), 1e-12)) << X->translation().transpose();
    }
  EXPECT_FALSE(g.objects[0].frame("cell_3_1"));
  EXPECT_FALSE(g.objects[0].frame("cell_{row}_{col}"));
  ASSERT_TRUE(g.objects[1].frame("cell_3_1"));
  EXPECT_NEAR(g.objects[1].frame("cell_3_1")->translation().x(), 2, 1e-12);
  std::vector<std::string> names = wc.frame_names(1);
  EXPECT_THAT(names, ::testing::ElementsAre("origin", "top", "cell_1_1", "cell_2_1", "cell_3_1"));
  // No copies at a count of 0.
  Workcell none = must_compile("objects:\n  - {type: grid, name: G, rows: 0}\n");
  EXPECT_EQ(build_geometry(none, diag).objects[0].shapes.size(), 1u);
}

TEST_F(Geometry, ARepeatCountThatIsNoWholeNumberIsAnErrorOfTheObject) {
  options.library_dirs.push_back(type_dir({{"grid", kGrid}}));
  EXPECT_THAT(first_error("objects:\n  - {type: grid, name: G, scale: 0.5}\n"),
              ::testing::HasSubstr("a repeated shape of 'G' (type 'grid'): the count of repeat counter 'col' (cols * scale) is 1.5, "
                                   "expected a whole number from 0 to 10000"));
  diag = Diagnostics{};
  EXPECT_THAT(first_error("parameters:\n  big: {value: 1e6}\nobjects:\n  - {type: grid, name: G, scale: big}\n"),
              ::testing::HasSubstr("is 3000000, expected a whole number from 0 to 10000"));
  diag = Diagnostics{};
  EXPECT_THAT(first_error("objects:\n  - {type: grid, name: G, cols: 1000, rows: 1000}\n"),
              ::testing::HasSubstr("a repeated shape of 'G' (type 'grid'): its repeat makes 1e+06 copies, more than the 10000"));
  EXPECT_THAT(diag.format(sources), ::testing::HasSubstr("frame 'cell_{row}_{col}' of 'G' (type 'grid'): its repeat makes 1e+06 copies"));
}

TEST_F(Geometry, RepeatedFrameNamesNameEachCounterOnce) {
  auto error_of = [&](const std::string& frames) {
    diag = Diagnostics{};
    options.library_dirs = {type_dir({{"t", "sscs: 1\ntype: t\nattributes:\n  n: {type: integer, default: 2}\nframes:\n" + frames +
                                                "geometry:\n  - box: {size: [1, 1, 1]}\n"}})};
    return first_error("objects:\n  - {type: t, name: A}\n");
  };
  EXPECT_THAT(error_of("  s_{k}: {xyz: [k, 0, 0]}\n"), ::testing::HasSubstr("frame name 's_{k}' names '{k}', but the frame has no 'repeat'"));
  EXPECT_THAT(error_of("  s_{i}: {xyz: [i, 0, 0], repeat: {k: n}}\n"),
              ::testing::HasSubstr("frame name 's_{i}' names '{i}', which is not a counter of its repeat (k)"));
  EXPECT_THAT(error_of("  s: {xyz: [k, 0, 0], repeat: {k: n}}\n"),
              ::testing::HasSubstr("frame name 's' must name counter 'k' once, as {k}, so that each copy has a name of its own"));
  EXPECT_THAT(error_of("  \"{k}s\": {repeat: {k: n}}\n"), ::testing::HasSubstr("expected a name for a frame"));
  EXPECT_THAT(error_of("  s_{k: {repeat: {k: n}}\n"), ::testing::HasSubstr("frame name 's_{k' has a '{' without its '}'"));
  EXPECT_THAT(error_of("  s_{k}: {repeat: {n: 2}}\n"), ::testing::HasSubstr("names '{k}', which is not a counter"));
  EXPECT_THAT(error_of("  s_{n}: {repeat: {n: 2}}\n"), ::testing::HasSubstr("repeat counter 'n' has the name of an attribute of 't'"));
  EXPECT_THAT(error_of("  s_{k}: {xyz: [j, 0, 0], repeat: {k: n}}\n"), ::testing::HasSubstr("uses 'j', which is not an attribute of type 't'"));
  EXPECT_THAT(error_of("  s_{k}: {repeat: {k: {count: n, pich: [1, 0, 0]}}}\n"), ::testing::HasSubstr("did you mean 'pitch'"));
  EXPECT_THAT(error_of("  s_{k}: {repeat: [k, n]}\n"), ::testing::HasSubstr("expected a map of counters"));
}

TEST_F(Geometry, AnObjectAtAFrameOfAnotherStandsThereAndMovesWithIt) {
  // `at: OBJECT.FRAME` makes OBJECT the parent and places the object in that frame: its location
  // and orientation are offsets in it. Array instances name their frame with {i} {j} {k}.
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: R, length: 20, width: 10, height: 6, location: [5, 0, 0], orientation: [0, 0, 90]}\n"
      "  - {type: drum_rack, name: K, parent: R, location: [2, 1, 0], bays: 2, levels: 2, level_height: 1.5}\n"
      "  - type: drum\n    array: {count: [3, 2, 2], name: \"D_{k}_{j}_{i}\"}\n    at: \"K.slot_{k}_{j}_{i}\"\n"
      "  - {type: drum, name: Up, at: K.slot_2_2_3, location: [0, 0, 0.5], orientation: [0, 0, 30]}\n");
  GeometryModel g = build_geometry(wc, diag);
  const int k = wc.find_object("K");
  for (int level = 1; level <= 2; ++level)
    for (int bay = 1; bay <= 2; ++bay)
      for (int position = 1; position <= 3; ++position) {
        const std::string slot = fmt::format("slot_{}_{}_{}", level, bay, position);
        const int d = wc.find_object(fmt::format("D_{}_{}_{}", level, bay, position));
        ASSERT_GE(d, 0) << slot;
        EXPECT_EQ(wc.objects[d].parent, k);
        EXPECT_TRUE(g.objects[d].X_world_object.isApprox(*g.objects[k].frame(slot), 1e-12)) << slot;
      }
  const int up = wc.find_object("Up");
  const Eigen::Isometry3d expected = *g.objects[k].frame("slot_2_2_3") * Eigen::Translation3d(0, 0, 0.5) *
                                     Eigen::AngleAxisd(30 * kPi / 180, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(g.objects[up].X_world_object.isApprox(expected, 1e-12));
  EXPECT_TRUE(g.objects[up].X_parent_at.isApprox(*wc.named_frame(k, "slot_2_2_3"), 1e-12));
  // The rack's levels decide which frames there are: level 3 of a two-level rack is none.
  diag = Diagnostics{};
  EXPECT_THAT(first_error("objects:\n  - {type: drum_rack, name: K, levels: 2}\n  - {type: drum, name: D, at: K.slot_3_1_1}\n"),
              ::testing::HasSubstr("'slot_3_1_1' is no named frame of K (type 'drum_rack'); its frames: top, slot_{level}_{bay}_{position} (level 1 to 2, bay 1 to 3, position 1 to 3),"));
  diag = Diagnostics{};
  EXPECT_THAT(first_error("objects:\n  - {type: drum_rack, name: K}\n  - {type: drum, name: D, at: Kk.slot_1_1_1}\n"),
              ::testing::HasSubstr("'at' names unknown object 'Kk' (did you mean 'K'?)"));
  diag = Diagnostics{};
  EXPECT_THAT(first_error("objects:\n  - {type: drum_rack, name: K}\n  - {type: drum, name: D, at: K}\n"),
              ::testing::HasSubstr("expected OBJECT.FRAME for 'at'"));
  diag = Diagnostics{};
  EXPECT_THAT(first_error("objects:\n  - {type: drum_rack, name: K}\n  - {type: drum, name: D, parent: K, at: K.slot_1_1_1}\n"),
              ::testing::HasSubstr("an object is placed by 'parent' or by 'at'"));
}

TEST_F(Geometry, ARacksPositionsNumberedAlongTheRunAreItsSlots) {
  // position_{level}_{n} and top_{n} are slot_{level}_{bay}_{position} numbered along the run.
  for (const char* rack : {"{type: drum_rack, name: K, bays: 3, positions: 4, levels: 2}", "{type: pallet_rack, name: K, bays: 5}"}) {
    Workcell wc = must_compile(std::string("objects:\n  - ") + rack + "\n");
    GeometryModel g = build_geometry(wc, diag);
    const ObjectGeometry& k = g.objects[0];
    const int bays = static_cast<int>(value(wc, "K.bays")), positions = static_cast<int>(value(wc, "K.positions"));
    const int levels = static_cast<int>(value(wc, "K.levels"));
    for (int level = 1; level <= levels; ++level)
      for (int bay = 1; bay <= bays; ++bay)
        for (int q = 1; q <= positions; ++q) {
          const int n = (bay - 1) * positions + q;
          const Eigen::Isometry3d* slot = k.frame(fmt::format("slot_{}_{}_{}", level, bay, q));
          const Eigen::Isometry3d* along = k.frame(fmt::format("position_{}_{}", level, n));
          ASSERT_TRUE(slot && along) << rack << " " << level << " " << n;
          EXPECT_TRUE(slot->isApprox(*along, 1e-12)) << rack << " " << level << " " << n;
          if (level == levels) {
            ASSERT_TRUE(k.frame(fmt::format("top_{}", n)));
            EXPECT_TRUE(k.frame(fmt::format("top_{}", n))->isApprox(*slot, 1e-12));
          }
        }
    EXPECT_FALSE(k.frame(fmt::format("position_1_{}", bays * positions + 1)));
  }
}

}  // namespace
}  // namespace sscs::testing
