#include "vtkSoftBodyConditionOutput.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkUnstructuredGrid.h"

#include <string>

namespace
{

void AddVector(vtkFieldData* field, const std::string& name, const softbody::Vec3& v)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name.c_str());
  array->SetNumberOfComponents(3);
  array->InsertNextTuple3(v.x(), v.y(), v.z());
  field->AddArray(array);
}

} // namespace

//------------------------------------------------------------------------------
void vtkSoftBodyConditionOutput::Add(
  const softbody::ConditionReadout& readout, vtkUnstructuredGrid* output)
{
  if (!readout.reactions.empty() &&
    static_cast<vtkIdType>(readout.reactions.size()) == output->GetNumberOfPoints())
  {
    vtkNew<vtkDoubleArray> reaction;
    reaction->SetName("Reaction");
    reaction->SetNumberOfComponents(3);
    reaction->SetNumberOfTuples(static_cast<vtkIdType>(readout.reactions.size()));
    for (std::size_t i = 0; i < readout.reactions.size(); ++i)
    {
      const softbody::Vec3& r = readout.reactions[i];
      reaction->SetTuple3(static_cast<vtkIdType>(i), r.x(), r.y(), r.z());
    }
    output->GetPointData()->AddArray(reaction);
  }
  for (const softbody::ConditionTotal& total : readout.totals)
  {
    AddVector(output->GetFieldData(), total.name + " Force", total.force);
    AddVector(output->GetFieldData(), total.name + " Moment", total.moment);
  }
}
