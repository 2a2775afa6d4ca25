#include "vtkSoftBodyCollisionRules.h"

#include "vtkSoftBodySettings.h"

namespace
{
/// The contact settings of the selected method (core keeps one per method).
const softbody::CollisionSettings& SelectedCollisions(const vtkSoftBodyCoreSettings& settings)
{
  return settings.Method == vtkSoftBodyParameters::MASS_SPRING ? settings.Scene.collisions
                                                               : settings.Pbd.collisions;
}
}

//------------------------------------------------------------------------------
bool vtkSoftBodyCollisionRules::CollisionsOn(const vtkSoftBodyCoreSettings& settings)
{
  return SelectedCollisions(settings).mode != softbody::CollisionMode::Off;
}

//------------------------------------------------------------------------------
bool vtkSoftBodyCollisionRules::BodiesCollide(const vtkSoftBodyCoreSettings& settings)
{
  const softbody::CollisionMode mode = SelectedCollisions(settings).mode;
  return mode == softbody::CollisionMode::ObstaclesAndBodies ||
    mode == softbody::CollisionMode::ObstaclesBodiesAndSelf;
}
