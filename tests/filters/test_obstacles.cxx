// filter.obstacles: the Obstacles input (port 2). A body dropped onto a sphere stays outside it
// (and sinks in with Collisions Off, so the check can fail); a time-dependent obstacle is
// requested at the frame times and pushes a body along (cached frames are served without
// fetching it again; a change of its source re-simulates); bad collision values are refused
// quoting them; Device GPU with obstacles falls back to the CPU with a warning that says why.
#include "filter_test_support.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSphereSource.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <cmath>

namespace
{
using SDDP = vtkStreamingDemandDrivenPipeline;

/// A wall x = X0 + Speed t (two triangles, normal +x, 2 m square) at the requested time; it
/// advertises the time range [0, 100] and counts its executions and the times asked of it.
class MovingWallSource : public vtkPolyDataAlgorithm
{
public:
  static MovingWallSource* New();
  vtkTypeMacro(MovingWallSource, vtkPolyDataAlgorithm)
  vtkSetMacro(Speed, double);
  double X0 = -0.1;
  double Speed = 0.5;
  std::vector<double> TimesAsked;

protected:
  MovingWallSource() { this->SetNumberOfInputPorts(0); }
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    const double range[2] = { 0.0, 100.0 };
    out->GetInformationObject(0)->Set(SDDP::TIME_RANGE(), range, 2);
    return 1;
  }
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
  {
    vtkInformation* info = out->GetInformationObject(0);
    const double t = info->Has(SDDP::UPDATE_TIME_STEP()) ? info->Get(SDDP::UPDATE_TIME_STEP()) : 0.0;
    this->TimesAsked.push_back(t);
    const double x = this->X0 + this->Speed * t;
    vtkNew<vtkPoints> points;
    points->InsertNextPoint(x, -1, -1);
    points->InsertNextPoint(x, 1, -1);
    points->InsertNextPoint(x, 1, 1);
    points->InsertNextPoint(x, -1, 1);
    vtkNew<vtkCellArray> polys;
    const vtkIdType quad[4] = { 0, 1, 2, 3 }; // counter-clockwise seen from +x
    polys->InsertNextCell(4, quad);
    vtkPolyData* output = vtkPolyData::GetData(out);
    output->SetPoints(points);
    output->SetPolys(polys);
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), t);
    return 1;
  }
};
vtkStandardNewMacro(MovingWallSource);

double MinDistanceTo(vtkUnstructuredGrid* mesh, const double center[3])
{
  double nearest = 1e300;
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double p[3];
    mesh->GetPoint(i, p);
    nearest = std::min(nearest, std::sqrt(vtkMath::Distance2BetweenPoints(p, center)));
  }
  return nearest;
}

void CheckRefused(vtkUnstructuredGrid* box, void (*set)(vtkSoftBodyFilter*), const char* name,
  const char* value)
{
  sbtest::CapturedFilter f(box);
  f.Filter->SetEndTime(0.1);
  set(f.Filter);
  SB_CHECK(!f.Update(0.04), name << " " << value << " was accepted");
  SB_CHECK(f.Messages->ErrorContains(name) && f.Messages->ErrorContains(value),
    "the refusal of " << name << " " << value << " does not quote it: " << f.Messages->AllErrors());
}
} // namespace

int main()
{
  // 1. A static sphere (r = 0.2 m, centre z = 0.2) under a 0.15 m box dropped from above; no
  // floor. Its triangles lie inside the true sphere by at most r (1 - cos(pi / 16)) = 3.8 mm.
  {
    const double center[3] = { 0.0, 0.0, 0.2 };
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(center[0], center[1], center[2]);
    sphere->SetRadius(0.2);
    sphere->SetThetaResolution(32);
    sphere->SetPhiResolution(32);
    auto box = sbtest::MakeTetBox(3, 3, 3, 0.05, { -0.07, -0.075, 0.5 });
    double withObstacle = 0.0;
    for (int collisions : { vtkSoftBodyFilter::COLLISIONS_OBSTACLES, vtkSoftBodyFilter::COLLISIONS_OFF })
    {
      sbtest::CapturedFilter f(box);
      f.Filter->AddObstacleConnection(sphere->GetOutputPort());
      f.Filter->SetFloor(0);
      f.Filter->SetCollisions(collisions);
      f.Filter->SetEndTime(0.6);
      double nearest = 1e300;
      for (double t : { 0.2, 0.3, 0.4, 0.5, 0.6 })
      {
        SB_CHECK(f.Update(t), f.Messages->AllErrors());
        nearest = std::min(nearest, MinDistanceTo(f.Mesh(), center));
      }
      std::cout << "Collisions " << collisions << ": nearest point " << nearest << " m from the sphere's centre\n";
      if (collisions == vtkSoftBodyFilter::COLLISIONS_OBSTACLES)
      {
        withObstacle = nearest;
        const std::vector<std::string> plan = sbtest::FieldStrings(f.Mesh(), "Plan");
        SB_CHECK(std::find(plan.begin(), plan.end(), "collision detection: obstacles") != plan.end(),
          "the plan does not list the obstacle detection");
      }
      else
      {
        SB_CHECK(nearest < 0.15, "with Collisions Off the body should fall into the sphere");
      }
    }
    SB_CHECK(withObstacle > 0.2 * std::cos(3.14159265358979 / 16) - 1e-6,
      "a point went into the sphere: " << withObstacle << " m from its centre");
  }

  // 2. A moving wall pushes a box resting on a frictionless floor: it meets the box at 0.3 s.
  {
    auto box = sbtest::MakeTetBox(3, 3, 3, 0.04, { 0.05, -0.06, 0.0 });
    vtkNew<MovingWallSource> wall;
    sbtest::CapturedFilter f(box);
    f.Filter->AddObstacleConnection(wall->GetOutputPort());
    f.Filter->SetStaticFriction(0.0);
    f.Filter->SetDynamicFriction(0.0);
    f.Filter->SetEndTime(1.0);
    f.Filter->SetFrameInterval(0.04);
    SB_CHECK(f.Update(0.6), f.Messages->AllErrors());
    const double wallX = -0.1 + 0.5 * 0.6;
    double leftmost = 1e300;
    for (vtkIdType i = 0; i < f.Mesh()->GetNumberOfPoints(); ++i)
    {
      leftmost = std::min(leftmost, f.Mesh()->GetPoint(i)[0]);
    }
    std::cout << "moving wall at x = " << wallX << ", leftmost point " << leftmost << "\n";
    SB_CHECK(leftmost > wallX, "the body is behind the moving wall: " << leftmost << " < " << wallX);
    SB_CHECK(std::abs(sbtest::FieldValue(f.Mesh(), "SimulationTime") - 0.6) < 1e-12, "not at 0.6 s");
    // Every frame time from 0 to 0.6 s was asked of the wall (and nothing much more).
    const std::size_t asked = wall->TimesAsked.size();
    for (int k = 0; k <= 15; ++k)
    {
      const double t = k * 0.04;
      SB_CHECK(std::find(wall->TimesAsked.begin(), wall->TimesAsked.end(), t) != wall->TimesAsked.end(),
        "the wall was never asked for t = " << t);
    }
    SB_CHECK(asked <= 17, "the wall executed " << asked << " times for 16 frame times");

    // A cached frame needs no obstacle and no step; a changed wall speed simulates again.
    const unsigned long long steps = f.Filter->GetSimulatedStepsTotal();
    const std::vector<double> at04 = [&] {
      SB_CHECK(f.Update(0.4), f.Messages->AllErrors());
      return sbtest::PointsOf(f.Mesh());
    }();
    SB_CHECK(f.Filter->GetSimulatedStepsTotal() == steps, "a cached frame was simulated again");
    SB_CHECK(wall->TimesAsked.size() == asked, "a cached frame fetched the obstacle again");
    wall->SetSpeed(1.0);
    SB_CHECK(f.Update(0.4), f.Messages->AllErrors());
    SB_CHECK(f.Filter->GetSimulatedStepsTotal() > steps, "a faster wall did not re-simulate");
    SB_CHECK(!sbtest::BitwiseEqual(sbtest::PointsOf(f.Mesh()), at04), "a faster wall left the frame as it was");
  }

  // 3. Bad values are refused, quoting them.
  {
    auto box = sbtest::MakeTetBox(2, 2, 2, 0.05, { 0.0, 0.0, 0.1 });
    CheckRefused(box, [](vtkSoftBodyFilter* f) { f->SetCollisionMargin(-0.5); }, "CollisionMargin", "-0.5");
    CheckRefused(box, [](vtkSoftBodyFilter* f) { f->SetStaticFriction(-1.0); }, "StaticFriction", "-1");
    CheckRefused(box, [](vtkSoftBodyFilter* f) { f->SetDynamicFriction(-2.0); }, "DynamicFriction", "-2");
    CheckRefused(box, [](vtkSoftBodyFilter* f) { f->SetRestitution(1.5); }, "Restitution", "1.5");
    CheckRefused(box, [](vtkSoftBodyFilter* f) { f->SetCollisions(7); }, "Collisions", "7");
    CheckRefused(box, [](vtkSoftBodyFilter* f) { f->SetBroadPhase(9); }, "BroadPhase", "9");
  }

  // 4. Device GPU with an obstacle: the CPU, with a warning that says why.
  {
    auto box = sbtest::MakeTetBox(2, 2, 2, 0.05, { 0.0, 0.0, 0.1 });
    vtkNew<vtkSphereSource> sphere;
    sbtest::CapturedFilter f(box);
    f.Filter->AddObstacleConnection(sphere->GetOutputPort());
    f.Filter->SetDevice(vtkSoftBodyFilter::DEVICE_GPU_EGL);
    f.Filter->SetEndTime(0.1);
    SB_CHECK(f.Update(0.04), f.Messages->AllErrors());
    const std::string warnings = [&] {
      std::string all;
      for (const std::string& w : f.Messages->Warnings)
      {
        all += w;
      }
      return all;
    }();
    SB_CHECK(warnings.find("simulating on the CPU") != std::string::npos &&
        warnings.find("Obstacles input") != std::string::npos,
      "no fallback warning naming the obstacles: " << warnings);
    SB_CHECK(sbtest::FieldString(f.Mesh(), "Device") == "CPU", "Device = " << sbtest::FieldString(f.Mesh(), "Device"));
  }
  return sbtest::Result("filter.obstacles");
}
