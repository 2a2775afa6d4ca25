// filter.pinned_points: points flagged by the PinnedPointsArray never move (bitwise) and have
// zero velocity and inverse mass, while the rest of the body sags under gravity; any nonzero
// component pins, and "None" pins nothing.
#include "filter_test_support.h"

#include "vtkIntArray.h"
#include "vtkPolyData.h"

int main()
{
  // A horizontal bar held at its x = 0 end: a cantilever.
  auto bar = sbtest::MakeTetBox(6, 2, 2, 0.05, { 0.0, 0.0, 0.5 });
  vtkNew<vtkIntArray> pinned;
  pinned->SetName("Clamp");
  pinned->SetNumberOfComponents(2); // pinned when any component is nonzero (negative too)
  pinned->SetNumberOfTuples(bar->GetNumberOfPoints());
  std::vector<bool> isPinned(static_cast<std::size_t>(bar->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < bar->GetNumberOfPoints(); ++i)
  {
    double p[3];
    bar->GetPoint(i, p);
    isPinned[static_cast<std::size_t>(i)] = p[0] < 1e-6;
    pinned->SetTypedComponent(i, 0, 0);
    pinned->SetTypedComponent(i, 1, p[0] < 1e-6 ? -3 : 0);
  }
  bar->GetPointData()->AddArray(pinned);
  const std::vector<double> rest = sbtest::PointsOf(bar);

  sbtest::CapturedFilter f(bar);
  f.Filter->SetPinnedPointsArray("Clamp");
  f.Filter->SetYoungsModulus(2.0e4); // soft enough to sag visibly
  f.Filter->SetEndTime(0.5);
  f.Filter->SetFrameInterval(0.05);
  double tipSag = 0.0;
  for (double t : { 0.05, 0.25, 0.5 })
  {
    SB_CHECK(f.Update(t), f.Messages->AllErrors());
    const std::vector<double> now = sbtest::PointsOf(f.Mesh());
    vtkDataArray* velocity = f.Mesh()->GetPointData()->GetArray("Velocity");
    for (std::size_t i = 0; i < isPinned.size(); ++i)
    {
      if (isPinned[i])
      {
        SB_CHECK(std::memcmp(&now[3 * i], &rest[3 * i], 3 * sizeof(double)) == 0,
          "pinned point " << i << " moved at t = " << t);
        const double* v = velocity->GetTuple3(static_cast<vtkIdType>(i));
        SB_CHECK(v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0, "pinned point " << i << " has velocity");
      }
      else
      {
        tipSag = std::max(tipSag, rest[3 * i + 2] - now[3 * i + 2]);
      }
    }
  }
  SB_CHECK(tipSag > 1e-3, "the free end should sag (max drop " << tipSag << " m)");

  vtkPolyData* particles = vtkPolyData::SafeDownCast(f.Filter->GetOutputDataObject(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Particles)));
  vtkDataArray* inverseMass = particles->GetPointData()->GetArray("InverseMass");
  for (std::size_t i = 0; inverseMass && i < isPinned.size(); ++i)
  {
    const double w = inverseMass->GetTuple1(static_cast<vtkIdType>(i));
    SB_CHECK(isPinned[i] ? w == 0.0 : w > 0.0, "inverse mass of point " << i << " is " << w);
  }

  // "None" pins nothing: the whole bar falls.
  f.Filter->SetPinnedPointsArray("None");
  SB_CHECK(f.Update(0.25), f.Messages->AllErrors());
  const std::vector<double> free = sbtest::PointsOf(f.Mesh());
  SB_CHECK(free[2] < rest[2] - 0.1, "without pins point 0 falls (z " << free[2] << ")");

  SB_CHECK(f.Messages->Errors.empty(), f.Messages->AllErrors());
  return sbtest::Result("filter.pinned_points");
}
