#include "vtkSoftBodyStressOutput.h"
#include "vtkSoftBodyArrays.h"

#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include <array>
#include <cmath>

namespace
{
using vtkSoftBodyArrays::MakeScalarArray;

vtkSmartPointer<vtkDoubleArray> MakeTensorArray(
  const char* name, const std::vector<softbody::SymmetricTensor>& values)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(6);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    array->SetTypedTuple(static_cast<vtkIdType>(i), values[i].data());
  }
  return array;
}
} // namespace

void vtkSoftBodyStressOutput::Add(const softbody::TetStressField& field,
  const std::vector<softbody::Vec3>& restPositions, vtkUnstructuredGrid* output)
{
  const vtkIdType cells = output->GetNumberOfCells();
  if (field.empty() || static_cast<vtkIdType>(field.vonMises.size()) != cells ||
    static_cast<vtkIdType>(restPositions.size()) != output->GetNumberOfPoints())
  {
    return;
  }
  vtkCellData* cellData = output->GetCellData();
  cellData->AddArray(MakeTensorArray("GreenStrain", field.greenStrain));
  cellData->AddArray(MakeTensorArray("CauchyStress", field.cauchyStress));
  cellData->AddArray(MakeScalarArray("VonMisesStress", field.vonMises));
  cellData->AddArray(MakeScalarArray("StrainEnergyDensity", field.energyDensity));

  const vtkIdType points = output->GetNumberOfPoints();
  std::vector<softbody::SymmetricTensor> stress(static_cast<std::size_t>(points), softbody::SymmetricTensor{});
  std::vector<double> vonMises(static_cast<std::size_t>(points), 0.0), weight(vonMises);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cells; ++c)
  {
    const auto t = static_cast<std::size_t>(c);
    if (!std::isfinite(field.vonMises[t]))
    {
      continue;
    }
    output->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() != 4)
    {
      continue;
    }
    const double restVolume = std::abs(softbody::signedTetVolume(restPositions[ids->GetId(0)],
      restPositions[ids->GetId(1)], restPositions[ids->GetId(2)], restPositions[ids->GetId(3)]));
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      const auto i = static_cast<std::size_t>(ids->GetId(k));
      weight[i] += restVolume;
      vonMises[i] += restVolume * field.vonMises[t];
      for (std::size_t j = 0; j < 6; ++j)
      {
        stress[i][j] += restVolume * field.cauchyStress[t][j];
      }
    }
  }
  for (std::size_t i = 0; i < vonMises.size(); ++i)
  {
    const double w = weight[i] > 0.0 ? 1.0 / weight[i] : std::nan("");
    vonMises[i] *= w;
    for (double& component : stress[i])
    {
      component *= w;
    }
  }
  output->GetPointData()->AddArray(MakeScalarArray("VonMisesStress", vonMises));
  output->GetPointData()->AddArray(MakeTensorArray("CauchyStress", stress));
}
