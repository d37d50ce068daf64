// The report's example object sub-class: `newdrum`, a drum with a diameter and a height. In the
// report a sub-class answers getAttributeNum, getAttributeNames and getAttributeRef; here the
// plugin declares the same things once -- the attribute list (its length is getAttributeNum, its
// names getAttributeNames, each entry what getAttributeRef would point at: type, unit, default,
// limits) -- and the geometry as shapes sized by expressions over those attributes. sscs then
// treats `newdrum` like a type-library type: vaults place it, constraints read its attributes,
// checks and simulations use its geometry, `sscs types --plugins DIR` lists it.
//
//   objects:
//     - {name: D1, type: newdrum, location: [1, 2, 0], diameter: 0.6, fill_mass: 120 kg}
#include <sscs/plugin.hpp>

SSCS_PLUGIN(registry) {
  sscs::plugin::ObjectType drum;
  drum.name = "newdrum";
  drum.extends = "object";
  drum.description = "the report's new drum: a lidded steel drum sized by diameter and height";
  drum.color = "#3A6EA5";
  drum.attributes = {
      {"diameter", "length", "0.572", "0.2", "1.2", "", "outside diameter"},
      {"height", "length", "0.851", "0.3", "1.5", "", "outside height, lid closed"},
      {"wall", "length", "0.0012", "0.0005", "0.01", "", "wall thickness"},
      {"fill_mass", "mass", "0", "0", "400", "", "mass of the contents"},
      {"lid", "enum", "closed", "", "", "open,closed", ""},
  };
  drum.geometry = {
      sscs::plugin::Shape::cylinder("diameter/2", "height").at("0", "0", "height/2"),
      // the two rolling hoops, 2 cm proud of the shell, at a third and two thirds of the height
      sscs::plugin::Shape::cylinder("diameter/2 + 0.01", "0.02").at("0", "0", "height/3"),
      sscs::plugin::Shape::cylinder("diameter/2 + 0.01", "0.02").at("0", "0", "2*height/3"),
  };
  drum.frames = {{"top", {"0", "0", "height"}}};
  drum.mass = "22 + fill_mass";  // kg: the empty drum (a 55-gallon 1A2's 20-22 kg) and its contents
  registry.object_type(drum);
}
