#include "vtkSoftBodyFloorOutput.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <cmath>

//------------------------------------------------------------------------------
void vtkSoftBodyFloorOutput::Fill(bool floorOn, const double origin[3], const double normal[3],
  const double bodyBounds[6], vtkPolyData* output)
{
  output->Initialize();
  if (!floorOn)
  {
    return;
  }
  double n[3] = { normal[0], normal[1], normal[2] };
  if (vtkMath::Normalize(n) == 0.0)
  {
    return; // the filter refuses a zero normal before it gets here
  }

  // Center: the body's rest box center dropped onto the plane along the normal.
  const double center[3] = { 0.5 * (bodyBounds[0] + bodyBounds[1]),
    0.5 * (bodyBounds[2] + bodyBounds[3]), 0.5 * (bodyBounds[4] + bodyBounds[5]) };
  double toCenter[3];
  vtkMath::Subtract(center, origin, toCenter);
  const double height = vtkMath::Dot(toCenter, n);
  double c[3] = { center[0] - height * n[0], center[1] - height * n[1],
    center[2] - height * n[2] };

  // Half side = the box diagonal; a body of one point (zero diagonal) still gets a 2 m floor.
  double half = std::sqrt((bodyBounds[1] - bodyBounds[0]) * (bodyBounds[1] - bodyBounds[0]) +
    (bodyBounds[3] - bodyBounds[2]) * (bodyBounds[3] - bodyBounds[2]) +
    (bodyBounds[5] - bodyBounds[4]) * (bodyBounds[5] - bodyBounds[4]));
  if (!(half > 0.0))
  {
    half = 1.0;
  }

  // Two unit vectors spanning the plane (u, v, n right-handed, so the quad faces along n).
  double u[3];
  double v[3];
  vtkMath::Perpendiculars(n, u, v, 0.0);

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const double signs[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  for (const auto& s : signs)
  {
    points->InsertNextPoint(c[0] + half * (s[0] * u[0] + s[1] * v[0]),
      c[1] + half * (s[0] * u[1] + s[1] * v[1]), c[2] + half * (s[0] * u[2] + s[1] * v[2]));
    normals->InsertNextTuple(n);
  }
  vtkNew<vtkCellArray> quad;
  const vtkIdType ids[4] = { 0, 1, 2, 3 };
  quad->InsertNextCell(4, ids);
  output->SetPoints(points);
  output->SetPolys(quad);
  output->GetPointData()->SetNormals(normals);
}
