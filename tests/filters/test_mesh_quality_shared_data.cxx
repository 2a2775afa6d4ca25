// filter.mesh_quality_shared_data: the quality filter on SOFA's Armadillo_Tetra_4406.vtu, a
// public mesh with slivers, flags them; prints the report's numbers. Skipped (exit 77) when the
// shared data directory is absent.
#include "filter_test_support.h"

#include "vtkCellData.h"
#include "vtkSoftBodyMeshQuality.h"
#include "vtkTable.h"
#include "vtkXMLUnstructuredGridReader.h"

#include <fstream>

int main()
{
  const std::string path = std::string(SOFTBODY_SHARED_DATA_DIR) + "/sofa/Armadillo_Tetra_4406.vtu";
  if (!std::ifstream(path).good())
  {
    std::cout << "skipped: " << path << " not found" << std::endl;
    return 77;
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkSoftBodyMeshQuality> filter;
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(filter);
  messages->Observe(filter->GetExecutive());
  filter->SetInputConnection(reader->GetOutputPort());
  SB_CHECK(filter->GetExecutive()->Update() == 1, "the filter runs: " << messages->AllErrors());

  auto* mesh = vtkUnstructuredGrid::SafeDownCast(filter->GetOutputDataObject(0));
  vtkDataArray* sliver = mesh ? mesh->GetCellData()->GetArray("Sliver") : nullptr;
  vtkDataArray* angle = mesh ? mesh->GetCellData()->GetArray("MinDihedralAngle") : nullptr;
  SB_CHECK(sliver && angle, "Sliver and MinDihedralAngle arrays");
  if (!sliver || !angle)
  {
    return sbtest::Result("filter.mesh_quality_shared_data");
  }
  vtkIdType flagged = 0;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    flagged += sliver->GetTuple1(c) != 0.0 ? 1 : 0;
    SB_CHECK((sliver->GetTuple1(c) != 0.0) == (angle->GetTuple1(c) < filter->GetSliverAngle()) ||
        mesh->GetCellData()->GetArray("Degenerate")->GetTuple1(c) != 0.0,
      "cell " << c << ": Sliver flag agrees with its angle " << angle->GetTuple1(c));
  }
  const double slivers = sbtest::FieldValue(mesh, "SliverTets");
  SB_CHECK(slivers > 0.0 && slivers == double(flagged), "slivers are flagged and counted: " << slivers);
  SB_CHECK(sbtest::FieldValue(mesh, "MinDihedralAngle") < filter->GetSliverAngle(), "the worst angle is a sliver's");
  SB_CHECK(sbtest::FieldValue(mesh, "StableStepGain") >= 1.0, "truncation never lowers the step");

  std::cout << "Armadillo_Tetra_4406: " << mesh->GetNumberOfPoints() << " points, "
            << mesh->GetNumberOfCells() << " tets; slivers " << slivers << ", inverted "
            << sbtest::FieldValue(mesh, "InvertedTets") << ", degenerate "
            << sbtest::FieldValue(mesh, "DegenerateTets") << ", min dihedral "
            << sbtest::FieldValue(mesh, "MinDihedralAngle") << " deg; stable step "
            << sbtest::FieldValue(mesh, "StableTimeStep") << " s -> "
            << sbtest::FieldValue(mesh, "TruncatedStableTimeStep") << " s (x"
            << sbtest::FieldValue(mesh, "StableStepGain") << ") with MaxInverseMass "
            << sbtest::FieldValue(mesh, "SuggestedMaxInverseMass") << " 1/kg ("
            << sbtest::FieldValue(mesh, "TruncatedPoints") << " points, total mass "
            << sbtest::FieldValue(mesh, "TotalMass") << " -> "
            << sbtest::FieldValue(mesh, "TruncatedTotalMass") << " kg)" << std::endl;
  return sbtest::Result("filter.mesh_quality_shared_data");
}
