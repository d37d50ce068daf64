#include "core/written.h"

#include <utility>

namespace sscs {

namespace {
constexpr std::pair<AttrType, const char*> kAttrTypes[] = {
    {AttrType::Length, "length"},   {AttrType::Angle, "angle"},     {AttrType::Mass, "mass"},
    {AttrType::Time, "time"},       {AttrType::Number, "number"},   {AttrType::Integer, "integer"},
    {AttrType::Boolean, "boolean"}, {AttrType::String, "string"},   {AttrType::Enum, "enum"},
};
struct RelOpName {
  RelOp op;
  const char* name;
  const char* symbol;
};
constexpr RelOpName kRelOps[] = {
    {RelOp::LT, "LT", "<"}, {RelOp::GT, "GT", ">"}, {RelOp::EQ, "EQ", "=="}, {RelOp::LE, "LE", "<="}, {RelOp::GE, "GE", ">="},
};
}  // namespace

const char* attr_type_name(AttrType t) {
  for (auto& [type, name] : kAttrTypes)
    if (type == t) return name;
  return "?";
}

std::optional<AttrType> attr_type_from(std::string_view word) {
  for (auto& [type, name] : kAttrTypes)
    if (word == name) return type;
  return std::nullopt;
}

const char* relop_symbol(RelOp op) { return kRelOps[static_cast<int>(op)].symbol; }

std::optional<RelOp> relop_from(std::string_view word) {
  for (const RelOpName& r : kRelOps)
    if (word == r.name || word == r.symbol) return r.op;
  return std::nullopt;
}

}  // namespace sscs
