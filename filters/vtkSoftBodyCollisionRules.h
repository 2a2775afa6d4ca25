/**
 * @file   vtkSoftBodyCollisionRules.h
 * @brief  What the selected method's Collisions mode implies for the filter: whether the
 *         Obstacles input is read at all, and whether bodies must meet each other.
 */
#ifndef vtkSoftBodyCollisionRules_h
#define vtkSoftBodyCollisionRules_h

struct vtkSoftBodyCoreSettings;

namespace vtkSoftBodyCollisionRules
{
/// Whether the selected method's Collisions mode is other than Off.
bool CollisionsOn(const vtkSoftBodyCoreSettings& settings);

/// Whether the selected method's bodies collide with each other (Collisions with Bodies).
bool BodiesCollide(const vtkSoftBodyCoreSettings& settings);
}

#endif
