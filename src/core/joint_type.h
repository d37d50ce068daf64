#pragma once
/// The kinds of joint a device part hangs on its parent by: read from type files and URDFs (load),
/// held by the compiled device model.
#include <cstdint>

namespace sscs {

enum class JointType : uint8_t { Revolute, Prismatic, Fixed };

}  // namespace sscs
