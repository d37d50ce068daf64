#include "load/spec.h"

namespace sscs {

const char* constraint_kind_name(const ConstraintKind& kind) {
  return kConstraintKindNames[kind.index()];
}

}  // namespace sscs
