// filter.frame_cache: replaying cached frames is exact and costs no simulation steps; resuming
// from a cached frame gives bitwise the same states as running straight through; the cache
// survives EndTime changes, obeys its memory budget (frame 0 always kept), and is dropped when a
// parameter or the input changes.
#include "filter_test_support.h"

namespace
{
constexpr double kInterval = 0.02;

double FrameTime(int k)
{
  return k * kInterval;
}

void Configure(vtkSoftBodyFilter* filter)
{
  filter->SetFrameInterval(kInterval);
  filter->SetEndTime(0.2);
}

std::vector<double> Positions(sbtest::CapturedFilter& f, double t)
{
  SB_CHECK(f.Update(t), "update at " << t << ": " << f.Messages->AllErrors());
  return sbtest::PointsOf(f.Mesh());
}
} // namespace

int main()
{
  auto box = sbtest::MakeTetBox(3, 3, 3, 0.05, { 0.0, 0.0, 0.2 });

  // Frame 5, then 2, then 5 again: the replays are exact and run no step.
  sbtest::CapturedFilter a(box);
  Configure(a.Filter);
  const std::vector<double> first5 = Positions(a, FrameTime(5));
  const unsigned long long stepsAfter5 = a.Filter->GetSimulatedStepsTotal();
  const double stepCount5 = sbtest::FieldValue(a.Mesh(), "StepCount");
  SB_CHECK(stepsAfter5 > 0 && stepCount5 == double(stepsAfter5),
    "frame 5 took " << stepsAfter5 << " steps, StepCount says " << stepCount5);
  SB_CHECK(a.Filter->GetNumberOfCachedFrames() == 6, "frames 0..5 cached");
  SB_CHECK(!sbtest::BitwiseEqual(first5, sbtest::PointsOf(box)), "the body moved");

  const std::vector<double> replay2 = Positions(a, FrameTime(2));
  SB_CHECK(a.Filter->GetSimulatedStepsTotal() == stepsAfter5, "frame 2 replayed without stepping");
  SB_CHECK(!sbtest::BitwiseEqual(replay2, first5), "frame 2 differs from frame 5");

  const std::vector<double> replay5 = Positions(a, FrameTime(5));
  SB_CHECK(sbtest::BitwiseEqual(replay5, first5), "frame 5 replayed bitwise");
  SB_CHECK(a.Filter->GetSimulatedStepsTotal() == stepsAfter5, "frame 5 replayed without stepping");
  SB_CHECK(sbtest::FieldValue(a.Mesh(), "StepCount") == stepCount5, "same StepCount on replay");

  // A fresh filter going 3 then 5 resumes from frame 3 and lands on the same bits.
  {
    sbtest::CapturedFilter b(box);
    Configure(b.Filter);
    Positions(b, FrameTime(3));
    const std::vector<double> via3 = Positions(b, FrameTime(5));
    SB_CHECK(sbtest::BitwiseEqual(via3, first5), "3-then-5 equals 5 directly, bitwise");
    SB_CHECK(b.Filter->GetSimulatedStepsTotal() == stepsAfter5,
      "3-then-5 ran " << b.Filter->GetSimulatedStepsTotal() << " steps, direct ran " << stepsAfter5);
  }

  // EndTime does not change the motion: the cache survives it.
  a.Filter->SetEndTime(0.4);
  SB_CHECK(sbtest::BitwiseEqual(Positions(a, FrameTime(5)), first5), "same frame after EndTime change");
  SB_CHECK(a.Filter->GetSimulatedStepsTotal() == stepsAfter5, "EndTime change keeps the cache");

  // A zero budget keeps only frame 0: the same frame is simulated again, to the same bits.
  {
    sbtest::CapturedFilter c(box);
    Configure(c.Filter);
    c.Filter->SetCacheMemoryLimit(0);
    Positions(c, FrameTime(5));
    SB_CHECK(c.Filter->GetNumberOfCachedFrames() == 1,
      "zero budget: only frame 0 kept, got " << c.Filter->GetNumberOfCachedFrames());
    Positions(c, FrameTime(2)); // moves the simulation off frame 5
    const unsigned long long before = c.Filter->GetSimulatedStepsTotal();
    SB_CHECK(sbtest::BitwiseEqual(Positions(c, FrameTime(5)), first5), "recomputed frame 5 bitwise");
    SB_CHECK(c.Filter->GetSimulatedStepsTotal() > before, "evicted frames are simulated again");
  }

  // Parameter changes invalidate: stiffer material, other gravity.
  {
    a.Filter->SetYoungsModulus(4.0e5);
    const std::vector<double> stiffer = Positions(a, FrameTime(5));
    SB_CHECK(a.Filter->GetSimulatedStepsTotal() > stepsAfter5, "new material is simulated");
    SB_CHECK(!sbtest::BitwiseEqual(stiffer, first5), "YoungsModulus changes the result");
    a.Filter->SetYoungsModulus(1.0e5);
    SB_CHECK(sbtest::BitwiseEqual(Positions(a, FrameTime(5)), first5),
      "back to the old material, back to the old result");

    a.Filter->SetGravity(0.0, 0.0, -20.0);
    const std::vector<double> heavier = Positions(a, FrameTime(5));
    SB_CHECK(!sbtest::BitwiseEqual(heavier, first5), "Gravity changes the result");
    a.Filter->SetGravity(0.0, 0.0, -9.81);
  }

  // Properties the method ignores keep the cache: Mass-Spring reads no PBD/XPBD setting; the
  // key is the core settings actually produced.
  {
    Positions(a, FrameTime(5));
    const unsigned long long before = a.Filter->GetSimulatedStepsTotal();
    a.Filter->SetIterations(3);
    a.Filter->SetSubsteps(4);
    a.Filter->SetXPBDLinkCompliance(1.0);
    a.Filter->SetPBDLinkStiffness(0.5);
    a.Filter->SetSolver(vtkSoftBodyFilter::JACOBI);
    SB_CHECK(sbtest::BitwiseEqual(Positions(a, FrameTime(5)), first5), "same frame after ignored changes");
    SB_CHECK(a.Filter->GetSimulatedStepsTotal() == before,
      "Mass-Spring keeps its cache when PBD properties change (ran "
        << a.Filter->GetSimulatedStepsTotal() - before << " steps)");
  }
  // A value core refuses (it validates while it builds a simulation) keeps the cache: put back,
  // the frames are all still there, not thrown away with the refused simulation.
  {
    const unsigned long long before = a.Filter->GetSimulatedStepsTotal();
    const int cached = a.Filter->GetNumberOfCachedFrames();
    a.Filter->SetYoungsModulus(-1.0);
    SB_CHECK(!a.Update(FrameTime(5)), "YoungsModulus -1 is refused");
    SB_CHECK(a.Messages->ErrorContains("YoungsModulus"), "the error names YoungsModulus: " << a.Messages->AllErrors());
    a.Messages->Clear();
    a.Filter->SetYoungsModulus(1.0e5);
    SB_CHECK(sbtest::BitwiseEqual(Positions(a, FrameTime(5)), first5), "same frame after the refusal");
    SB_CHECK(a.Filter->GetSimulatedStepsTotal() == before && a.Filter->GetNumberOfCachedFrames() == cached,
      "the refusal kept the cache (ran " << a.Filter->GetSimulatedStepsTotal() - before << " steps, "
        << a.Filter->GetNumberOfCachedFrames() << " frames cached, were " << cached << ")");
  }
  {
    // Under XPBD, the PBD stiffnesses and the Mass-Spring damping are ignored; a compliance is not.
    sbtest::CapturedFilter x(box);
    Configure(x.Filter);
    x.Filter->SetMethod(vtkSoftBodyFilter::XPBD);
    const std::vector<double> xpbd5 = Positions(x, FrameTime(5));
    const unsigned long long before = x.Filter->GetSimulatedStepsTotal();
    x.Filter->SetPBDLinkStiffness(0.5);
    x.Filter->SetDampingTime(0.1);
    x.Filter->SetStrainLimit(1.2);
    SB_CHECK(sbtest::BitwiseEqual(Positions(x, FrameTime(5)), xpbd5), "XPBD: same frame after ignored changes");
    SB_CHECK(x.Filter->GetSimulatedStepsTotal() == before, "XPBD keeps its cache when Mass-Spring properties change");
    x.Filter->SetIterations(0); // refused by core's PBD set-up
    SB_CHECK(!x.Update(FrameTime(5)) && x.Messages->ErrorContains("Iterations"), "XPBD: Iterations 0 is refused");
    x.Messages->Clear();
    x.Filter->SetIterations(10);
    SB_CHECK(sbtest::BitwiseEqual(Positions(x, FrameTime(5)), xpbd5), "XPBD: same frame after the refusal");
    SB_CHECK(x.Filter->GetSimulatedStepsTotal() == before, "XPBD: the refusal kept the cache");
    x.Filter->SetXPBDLinkCompliance(1.0e-2);
    Positions(x, FrameTime(5));
    SB_CHECK(x.Filter->GetSimulatedStepsTotal() > before, "XPBD: a compliance change is simulated anew");
    SB_CHECK(x.Messages->Errors.empty(), x.Messages->AllErrors());
  }

  // Input changes invalidate: a shifted copy of the box falls the same way, shifted.
  {
    auto moved = sbtest::MakeTetBox(3, 3, 3, 0.05, { 0.0, 0.0, 0.2 });
    sbtest::CapturedFilter d(moved);
    Configure(d.Filter);
    Positions(d, FrameTime(5));
    const unsigned long long before = d.Filter->GetSimulatedStepsTotal();
    vtkPoints* points = moved->GetPoints();
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    {
      double p[3];
      points->GetPoint(i, p);
      points->SetPoint(i, p[0], p[1], p[2] + 0.1);
    }
    points->Modified();
    const std::vector<double> higher = Positions(d, FrameTime(5));
    SB_CHECK(d.Filter->GetSimulatedStepsTotal() > before, "a modified input is simulated anew");
    SB_CHECK(!higher.empty() && std::abs(higher[2] - first5[2] - 0.1) < 1e-6,
      "the raised body is 0.1 m higher at the same time (got " << higher[2] - first5[2] << ")");
  }

  SB_CHECK(a.Messages->Errors.empty(), a.Messages->AllErrors());
  return sbtest::Result("filter.frame_cache");
}
