#pragma once
/// The words every stage shares about written values: a scalar as written (text and mark), the
/// attribute types, the relations of `bound` and a constraint's severity. The load stage reads
/// them; the compiled model keeps a type's defaults as written.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/source.h"

namespace sscs {

/// A scalar as written. `null` for an explicit `~`/`null`/empty value.
struct Scalar {
  std::string text;
  SourceMark mark;
  bool quoted = false;
  bool null = false;
  bool present = false;  ///< false when the key was absent
};

enum class AttrType : uint8_t { Length, Angle, Mass, Time, Number, Integer, Boolean, String, Enum };
const char* attr_type_name(AttrType t);
std::optional<AttrType> attr_type_from(std::string_view word);

enum class RelOp : uint8_t { LT, GT, EQ, LE, GE };
const char* relop_symbol(RelOp op);
std::optional<RelOp> relop_from(std::string_view word);

enum class Severity : uint8_t { Error, Warning };

/// The actions a scenario step names, in the order of its alternatives.
inline constexpr const char* kStepActionNames[] = {"move_joints", "move_to", "grasp", "release", "wait", "parallel"};

}  // namespace sscs
