#include "model/run.h"

namespace cmcsurf {

const char* constraint_name(Constraint c) {
  switch (c) {
    case Constraint::kVolume: return "volume";
    case Constraint::kMass: return "mass";
    case Constraint::kComponents: return "components";
  }
  return "?";
}

}  // namespace cmcsurf
