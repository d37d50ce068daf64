// final.yaml (campaign-format.md, "What a campaign run writes"): the vault as a run leaves it,
// written back as a vault file that compiles to every object where the run left it.
#include <cmath>
#include <random>
#include <set>

#include <fmt/format.h>

#include "core/pose.h"
#include "core/units.h"
#include "geometry/geometry.h"
#include "model/device.h"
#include "pipeline/resolved.h"
#include "vault_fixture.h"

namespace sscs::testing {
namespace {

using FinalVault = VaultTest;

// Arrays, `at:` frames of rotated racks, expressions, a parent chain (a drum on a turned pallet),
// typed parameters a constraint names, string and enum attributes, a device with joints.
const char* kVault = R"YAML(parameters:
  pitch: {value: 3 m, type: length}
  rows: {value: 2, type: integer}
  fill: 150 kg
  lean: 12 deg
  open: true
objects:
  - {type: room, name: Hall, length: 20 m, width: 10 m, height: 7 m}
  - type: drum_rack
    array: {name: "Row_{i}", count: [rows], pitch: [pitch, 0, 0]}
    parent: Hall
    location: [6, 2, 0]
    orientation: [0, 0, "(-1)^i*rad(90)"]
  - type: drum
    array: {name: "D_{i}_{j}", count: [rows, 3]}
    at: "Row_{i}.position_1_{j}"
    fill_mass: "fill + 10 * j"
    lid: open
  - {type: bridge_crane, name: Crane, parent: Hall, location: [0.4, 0.6, 0], runway_length: 19 m, span: 8.8 m,
     rail_height: 6 m, lift: 5 m, travel: 3 m, traverse: 2 m}
  - {type: pallet, name: P, parent: Hall, location: [2, 8, 0], orientation: [0, 0, lean]}
  - {type: drum, name: Rider, parent: P, location: [0.3, 0.3, 0.15], orientation: [0, 0, 45]}
constraints:
  - {name: the parameters hold, expr: "pitch > 2 m && rows >= 2 && fill < 200 kg && lean < 15 deg && open"}
)YAML";

double pose_gap(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff(); }

TEST_F(FinalVault, CompilesToEveryObjectWhereTheRunLeftIt) {
  const Workcell wc = must_compile(kVault);
  ASSERT_FALSE(wc.objects.empty());
  const GeometryModel geometry = build_geometry(wc, diag);
  std::mt19937 rng(3737);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const size_t n = wc.objects.size();
    FinalState end;
    end.t = 100 + trial;
    end.moved.assign(n, 0);
    end.gone.assign(n, 0);
    end.attributes.resize(n);
    std::set<int> parents;
    for (const Object& o : wc.objects)
      if (o.parent >= 0) parents.insert(o.parent);
    for (size_t o = 0; o < n; ++o) {
      Eigen::Isometry3d X = geometry.objects[o].X_world_object;
      const ObjectType& type = wc.types[wc.objects[o].type];
      if (geometry.objects[o].device) {  // its joints somewhere within their limits
        const Device& m = *geometry.objects[o].device;
        const double* attributes = &wc.values[wc.objects[o].first_slot + kFirstAttributeSlot];
        for (int k = 0; k < m.dof(); ++k) {
          const AttributeDef& def = type.attributes[m.joint(k).attribute];
          end.attributes[o].emplace_back(m.joint(k).attribute, def.lower(attributes) + unit(rng) * (def.upper(attributes) - def.lower(attributes)));
        }
      } else if (!type.container && unit(rng) < 0.5) {  // moved: anywhere, turned any way
        X = make_pose(Eigen::Vector3d(20 * unit(rng), 10 * unit(rng), 3 * unit(rng)),
                      Eigen::Vector3d((2 * unit(rng) - 1) * kPi, (unit(rng) - 0.5) * kPi * 0.98, (2 * unit(rng) - 1) * kPi));
        end.moved[o] = 1;
      } else if (!parents.count(static_cast<int>(o)) && !type.container && unit(rng) < 0.2) {
        end.gone[o] = 1;  // a load that never arrived
      }
      end.X_world.push_back(X);
    }
    const std::string text = final_vault_text(wc, sources, end, "campaign test", false);

    Sources again;
    Diagnostics diag_again;
    const uint32_t file = again.add("final.yaml", text);
    auto spec = load_vault(file, again, diag_again);
    std::optional<Workcell> back;
    if (spec && !diag_again.has_errors()) back = compile_vault(*spec, options, again, diag_again);
    ASSERT_TRUE(back && !diag_again.has_errors()) << diag_again.format(again) << "\n" << text;
    EXPECT_TRUE(diag_again.warnings().empty()) << diag_again.format(again);
    const GeometryModel geometry_back = build_geometry(*back, diag_again);
    for (size_t o = 0; o < n; ++o) {
      const Object& obj = wc.objects[o];
      const int b = back->find_object(obj.name);
      if (end.gone[o]) {
        EXPECT_EQ(b, -1) << obj.name << " never arrived";
        continue;
      }
      ASSERT_GE(b, 0) << obj.name;
      // Where the run left it (to the 1e-9 m and 1e-9 degree the file writes moved poses with).
      EXPECT_LT(pose_gap(geometry_back.objects[b].X_world_object, end.X_world[o]), 1e-8) << obj.name << "\n" << text;
      const ObjectType& type = wc.types[obj.type];
      EXPECT_EQ(back->types[back->objects[b].type].name, type.name);
      for (size_t a = 0; a < type.attributes.size(); ++a) {
        const uint32_t slot = obj.first_slot + kFirstAttributeSlot + a, slot_back = back->objects[b].first_slot + kFirstAttributeSlot + a;
        double want = wc.values[slot];
        for (const auto& [index, value] : end.attributes[o])
          if (index == static_cast<int>(a)) want = value;
        EXPECT_NEAR(back->values[slot_back], want, 1e-9) << obj.name << "." << type.attributes[a].name;
        EXPECT_EQ(back->texts[slot_back], wc.texts[slot]) << obj.name << "." << type.attributes[a].name;
      }
    }
    ASSERT_EQ(back->parameters.size(), wc.parameters.size());
    for (size_t p = 0; p < wc.parameters.size(); ++p) {
      EXPECT_EQ(back->parameters[p].dim, wc.parameters[p].dim) << wc.parameters[p].name;
      EXPECT_NEAR(back->values[back->parameters[p].slot], wc.values[wc.parameters[p].slot], 1e-12) << wc.parameters[p].name;
    }
    EXPECT_EQ(back->constraints.size(), wc.constraints.size());
    if (HasFailure()) break;
  }
}

TEST_F(FinalVault, PinsTheParametersTheRunUsed) {
  options.overrides = {{"pitch", "4.5 m"}, {"rows", "3"}};
  const Workcell wc = must_compile(kVault);
  const GeometryModel geometry = build_geometry(wc, diag);
  FinalState end;
  for (const ObjectGeometry& g : geometry.objects) end.X_world.push_back(g.X_world_object);
  end.moved.assign(wc.objects.size(), 0);
  end.gone.assign(wc.objects.size(), 0);
  end.attributes.resize(wc.objects.size());
  const std::string text = final_vault_text(wc, sources, end, "campaign test", false);
  EXPECT_NE(text.find("pitch: \"4.5 m\""), std::string::npos) << text;
  EXPECT_NE(text.find("rows: {value: 3, type: integer}"), std::string::npos) << text;
  EXPECT_NE(text.find("name: Row_3"), std::string::npos) << text;
  EXPECT_NE(text.find("- {type: drum, name: D_1_1, at: Row_1.position_1_1, location: [0, 0, 0], color:"), std::string::npos) << text;
  EXPECT_NE(text.find("description: T as campaign test left it at 0 s"), std::string::npos) << text;
}

}  // namespace
}  // namespace sscs::testing
