// The glTF files sscs writes (render/gltf.h): read back byte by byte, the still model places
// every object, part and shape where the geometry does, and a run's animation gives, at each
// sample, the poses the run had (the scene a viewer plays is the scene the logs hold).
#include <cstring>

#include <nlohmann/json.hpp>

#include "model/device.h"
#include "render/gltf.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using Gltf = VaultTest;
using json = nlohmann::json;

struct Glb {
  json doc;
  std::string bin;
  /// The floats of accessor `a`, `width` a row.
  std::vector<float> floats(int a) const {
    const json& acc = doc["accessors"][a];
    const json& view = doc["bufferViews"][acc["bufferView"].get<int>()];
    const int width = acc["type"] == "SCALAR" ? 1 : acc["type"] == "VEC3" ? 3 : 4;
    const size_t stride = view.value("byteStride", width * 4);
    std::vector<float> out;
    for (size_t i = 0; i < acc["count"].get<size_t>(); ++i)
      for (int c = 0; c < width; ++c) {
        float v;
        std::memcpy(&v, bin.data() + view["byteOffset"].get<size_t>() + acc.value("byteOffset", 0) + i * stride + c * 4, 4);
        out.push_back(v);
      }
    return out;
  }
};

Glb read_glb(const std::string& bytes) {
  auto u32 = [&](size_t at) { uint32_t v; std::memcpy(&v, bytes.data() + at, 4); return v; };
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), bytes.size());
  EXPECT_EQ(u32(16), 0x4E4F534Au);
  Glb g;
  g.doc = json::parse(bytes.substr(20, u32(12)));
  const size_t bin_at = 20 + u32(12);
  if (bin_at < bytes.size()) {
    EXPECT_EQ(u32(bin_at + 4), 0x004E4942u);
    g.bin = bytes.substr(bin_at + 8, u32(bin_at));
  }
  return g;
}

int node_named(const json& doc, const std::string& name) {
  for (size_t i = 0; i < doc["nodes"].size(); ++i)
    if (doc["nodes"][i].value("name", "") == name) return static_cast<int>(i);
  return -1;
}

Eigen::Isometry3d local(const json& node) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (node.contains("translation")) X.translation() = Eigen::Vector3d(node["translation"][0], node["translation"][1], node["translation"][2]);
  if (node.contains("rotation"))
    X.linear() = Eigen::Quaterniond(node["rotation"][3].get<double>(), node["rotation"][0].get<double>(), node["rotation"][1].get<double>(),
                                    node["rotation"][2].get<double>()).toRotationMatrix();
  return X;
}

TEST_F(Gltf, StillModelPlacesObjectsPartsAndCamerasInAZUpRoot) {
  Workcell wc = must_compile(
      "objects:\n  - {type: room, name: Hall, length: 8, width: 6, height: 4}\n"
      "  - {type: drum, name: D, parent: Hall, location: [2, 1, 0], orientation: [0, 0, 30]}\n"
      "  - {type: arm6, name: Arm, parent: Hall, location: [5, 3, 0], j2: -20, j3: 35}\n"
      "cameras:\n  side: {eye: [4, -6, 2], target: [4, 3, 1], fov: 50}\n");
  GeometryModel g = build_geometry(wc, diag);
  Expected<std::string> bytes = gltf_file(wc, g, {vault_cameras(wc, g), nullptr}, true);
  ASSERT_TRUE(bytes) << bytes.error();
  Glb glb = read_glb(*bytes);
  const json& doc = glb.doc;
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  const json& root = doc["nodes"][doc["scenes"][0]["nodes"][0].get<int>()];
  const Eigen::Isometry3d X_gltf_sscs = local(root);  // z up -> y up
  EXPECT_TRUE((X_gltf_sscs * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    const int n = node_named(doc, wc.objects[o].name);
    ASSERT_GE(n, 0) << wc.objects[o].name;
    EXPECT_TRUE(local(doc["nodes"][n]).isApprox(g.objects[o].X_world_object, 1e-9)) << wc.objects[o].name;
    EXPECT_EQ(doc["nodes"][n]["extras"]["sscs"]["object"], wc.objects[o].name);
  }
  EXPECT_EQ(doc["nodes"][node_named(doc, "Hall")]["extras"]["sscs"]["container"], true);
  // Every part of the arm at its pose in the arm's frame.
  const int arm = wc.find_object("Arm");
  const Device& device = *g.objects[arm].device;
  for (size_t p = 0; p < device.parts.size(); ++p) {
    const int n = node_named(doc, "Arm." + device.parts[p].name);
    ASSERT_GE(n, 0) << device.parts[p].name;
    EXPECT_TRUE(local(doc["nodes"][n]).isApprox(g.objects[arm].X_object_part[p], 1e-9)) << device.parts[p].name;
  }
  // The drum's mesh, placed by its shape node, spans the drum's world bounds.
  const int drum = wc.find_object("D");
  const json& drum_node = doc["nodes"][node_named(doc, "D")];
  Eigen::AlignedBox3d box;
  for (const json& child : drum_node["children"]) {
    const json& shape = doc["nodes"][child.get<int>()];
    const std::vector<float> pn = glb.floats(doc["meshes"][shape["mesh"].get<int>()]["primitives"][0]["attributes"]["POSITION"]);
    for (size_t i = 0; i < pn.size(); i += 3)
      box.extend(g.objects[drum].X_world_object * local(shape) * Eigen::Vector3d(pn[i], pn[i + 1], pn[i + 2]));
  }
  EXPECT_LT((box.min() - g.objects[drum].bbox_world.min()).norm(), 1e-3);
  EXPECT_LT((box.max() - g.objects[drum].bbox_world.max()).norm(), 1e-3);
  // The named camera looks from its eye at its target (down its -z).
  const int cam = node_named(doc, "side");
  ASSERT_GE(cam, 0);
  const Eigen::Isometry3d X_cam = local(doc["nodes"][cam]);
  EXPECT_TRUE(X_cam.translation().isApprox(Eigen::Vector3d(4, -6, 2), 1e-12));
  EXPECT_TRUE((X_cam.linear() * -Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(0, 9, -1).normalized(), 1e-9));
  EXPECT_NEAR(doc["cameras"][doc["nodes"][cam]["camera"].get<int>()]["perspective"]["yfov"].get<double>(), 50 * M_PI / 180, 1e-12);
  EXPECT_FALSE(doc.contains("animations"));  // nothing moves in a still model
}

TEST_F(Gltf, RunAnimationHoldsThePosesOfEverySample) {
  Workcell wc = must_compile(
      "objects:\n  - {type: arm6, name: Arm, location: [0, 0, 0]}\n"
      "  - {type: drum, name: D, location: [1.5, 0, 0]}\n  - {type: drum, name: Still, location: [-2, 0, 0]}\n");
  GeometryModel g = build_geometry(wc, diag);
  const int arm = wc.find_object("Arm"), drum = wc.find_object("D");
  const Device& device = *g.objects[arm].device;
  SceneAnimation run;
  run.times = {0, 0.5, 1.0, 1.5};
  run.moving = {arm, drum, wc.find_object("Still")};
  run.at = [&](double t) {
    ScenePose pose = ScenePose::of(g);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(device.dof());
    q[0] = t;           // the base turns
    q[1] = -0.3 * t;
    pose.X_object_part[arm] = device.part_poses(q);
    pose.X_world_object[drum].translation() += Eigen::Vector3d(0, 0, t);  // the drum is lifted
    return pose;
  };
  run.camera = [](double t, const ScenePose&) { return Camera{{5 - t, -5, 3}, {0, 0, 1}, 45}; };
  Expected<std::string> bytes = gltf_file(wc, g, {{}, &run}, true);
  ASSERT_TRUE(bytes) << bytes.error();
  Glb glb = read_glb(*bytes);
  const json& doc = glb.doc;
  ASSERT_EQ(doc["animations"].size(), 1u);
  const json& anim = doc["animations"][0];
  std::map<std::pair<int, std::string>, int> channel;  // (node, path) -> sampler
  for (const json& c : anim["channels"]) channel[{c["target"]["node"].get<int>(), c["target"]["path"].get<std::string>()}] = c["sampler"];
  auto samples = [&](int node, const std::string& path) {
    const int s = channel.at({node, path});
    EXPECT_EQ(glb.floats(anim["samplers"][s]["input"].get<int>()), std::vector<float>({0, 0.5, 1.0, 1.5}));
    return glb.floats(anim["samplers"][s]["output"].get<int>());
  };
  // The drum's translation, sample by sample.
  const std::vector<float> lift = samples(node_named(doc, "D"), "translation");
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(lift[3 * k + 2], 0.5 * k + g.objects[drum].X_world_object.translation().z(), 1e-6);
  // Each moving part's rotation is its pose at the sample's joint values.
  for (size_t p = 1; p < device.parts.size(); ++p) {
    const std::vector<float> quat = samples(node_named(doc, "Arm." + device.parts[p].name), "rotation");
    for (int k = 0; k < 4; ++k) {
      const Eigen::Quaterniond expected(run.at(0.5 * k).X_object_part[arm][p].linear());
      const Eigen::Quaterniond got(quat[4 * k + 3], quat[4 * k], quat[4 * k + 1], quat[4 * k + 2]);
      EXPECT_NEAR(std::abs(expected.dot(got)), 1.0, 1e-6) << device.parts[p].name << " at " << 0.5 * k;
    }
  }
  // What did not move has no channel: the still drum, the arm's base object.
  for (const char* still : {"Still", "Arm"}) EXPECT_FALSE(channel.count({node_named(doc, still), "translation"})) << still;
  // The run's camera moves with the run.
  const std::vector<float> eye = samples(node_named(doc, "run"), "translation");
  EXPECT_NEAR(eye[0], 5, 1e-6);
  EXPECT_NEAR(eye[9], 3.5, 1e-6);
  EXPECT_EQ(doc["nodes"][0]["extras"]["sscs"]["duration"], 1.5);
}

TEST_F(Gltf, NonFinitePosesAreAnErrorNotANull) {
  Workcell wc = must_compile("objects:\n  - {type: drum, name: D}\n");
  GeometryModel g = build_geometry(wc, diag);
  SceneAnimation run;
  run.times = {0, 1};
  run.moving = {0};
  run.at = [&](double t) {
    ScenePose pose = ScenePose::of(g);
    if (t > 0) pose.X_world_object[0].translation().x() = std::nan("");
    return pose;
  };
  Expected<std::string> bytes = gltf_file(wc, g, {{}, &run}, true);
  ASSERT_FALSE(bytes);
  EXPECT_NE(bytes.error().find("not a finite number"), std::string::npos) << bytes.error();
  run.at = [&](double t) {
    ScenePose pose = ScenePose::of(g);
    pose.X_world_object[0].translation().z() = t;
    return pose;
  };
  run.times = {0, 1, 1};
  bytes = gltf_file(wc, g, {{}, &run}, true);
  ASSERT_FALSE(bytes);
  EXPECT_NE(bytes.error().find("do not increase"), std::string::npos) << bytes.error();
}

}  // namespace
}  // namespace sscs::testing
