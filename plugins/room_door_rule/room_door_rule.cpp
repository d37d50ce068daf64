// The report's functional constraint: "if the room is higher than 15 units, the door must be 7
// units high; otherwise it must be lower than 7". A `plugin` constraint of class room_door_rule
// takes two attributes, the room's height and the door's, in that order:
//   - {name: door height rule, plugin: {class: room_door_rule, attributes: [Room1.height, Door1.height]}}
// Args (optional): {threshold: 15, door: 7} change the two numbers.
#include <sscs/plugin.hpp>

#include <cmath>
#include <string>

namespace {

sscs::plugin::Result room_door(const sscs::plugin::Inputs& in) {
  const double room = in.value(0), door = in.value(1);
  const double threshold = in.number("threshold", 15), standard = in.number("door", 7);
  const std::string u = in.unit(1);
  auto num = [](double x) { return std::to_string(x).substr(0, std::to_string(x).find('.') + 3); };
  if (room > threshold) {
    const double off = std::abs(door - standard);
    return sscs::plugin::Result::judge(off < 1e-9, -off, u,
                                       in.ref(0) + " = " + num(room) + " > " + num(threshold) + ", so " + in.ref(1) +
                                           " must be " + num(standard) + ": it is " + num(door));
  }
  return sscs::plugin::Result::judge(door < standard, standard - door, u,
                                     in.ref(0) + " = " + num(room) + " <= " + num(threshold) + ", so " + in.ref(1) +
                                         " must be lower than " + num(standard) + ": it is " + num(door));
}

}  // namespace

SSCS_PLUGIN(registry) {
  registry.constraint("room_door_rule", "a door is 7 high in a room higher than 15, else lower than 7", 2, 2, room_door);
}
