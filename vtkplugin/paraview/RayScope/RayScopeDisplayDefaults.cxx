// The defaults of the plugin's representations (RayScope.xml), registered
// with ParaView's settings when the plugin is loaded: the Ray Trace image
// (RayScopeImageRepresentation) shows its "Color" array as colors, with Map
// Scalars off, instead of through a color map. At priority 0, the lowest
// ParaView uses (site settings), so a user's or site's own setting of the same
// key wins.
#include "vtkSMSettings.h"

namespace {

constexpr const char* kDisplayDefaults = R"({
  "representations": {
    "RayScopeImageRepresentation": { "MapScalars": 0 }
  }
})";

struct RegisterDisplayDefaults {
  RegisterDisplayDefaults() {
    vtkSMSettings::GetInstance()->AddCollectionFromString(kDisplayDefaults, 0.0);
  }
};

const RegisterDisplayDefaults kRegistered;

}  // namespace
