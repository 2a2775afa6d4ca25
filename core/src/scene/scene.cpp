#include "softbody/scene/scene.h"

#include "softbody/common/validation.h"

namespace softbody
{

void validateScene(const Scene& scene)
{
  check::finite("Gravity", scene.gravity);
  // A floor nothing touches is not read, so it is not refused either.
  if (scene.floorActive())
  {
    check::finite("FloorOrigin", scene.floor.origin);
    check::nonZeroDirection("FloorNormal", scene.floor.normal);
  }
}

} // namespace softbody
