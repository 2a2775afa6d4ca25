#include "softbody/common/step_plan.h"

#include <stdexcept>

namespace softbody
{

const char* stageName(Stage stage)
{
  switch (stage)
  {
    case Stage::Forces:
      return "forces";
    case Stage::Integrate:
      return "integrate";
    case Stage::LinearSolve:
      return "linear solve";
    case Stage::StrainLimit:
      return "strain limit";
    case Stage::Floor:
      return "floor";
    case Stage::CollisionDetect:
      return "collision detection";
    case Stage::Contacts:
      return "contacts";
    case Stage::Predict:
      return "predict";
    case Stage::SolveLinks:
      return "solve links";
    case Stage::SolveTetElasticity:
      return "solve tet elasticity";
    case Stage::SolveVolumes:
      return "solve volumes";
    case Stage::SolveAttachments:
      return "solve attachments";
    case Stage::SolveContacts:
      return "solve contacts";
    case Stage::Residual:
      return "residual";
    case Stage::UpdateVelocities:
      return "velocity update";
    case Stage::ContactResponse:
      return "contact restitution";
    case Stage::UpdateLinks:
      return "links: plasticity + breaking";
    case Stage::DivergenceCheck:
      return "divergence check";
    case Stage::Transfers:
      return "transfers: host <-> GPU";
    case Stage::Count:
      break;
  }
  return "?";
}

void StepPlan::add(Stage stage, std::string detail)
{
  if (stage == Stage::Count || Runs[index(stage)])
  {
    // A planner bug, not a user error: each stage runs at most once per step.
    throw std::logic_error(std::string("stage planned twice: ") + stageName(stage));
  }
  Order.push_back(stage);
  Runs[index(stage)] = true;
  Details[index(stage)] = std::move(detail);
}

std::string StepPlan::label(Stage stage) const
{
  const std::string& detail = Details[index(stage)];
  return detail.empty() ? std::string(stageName(stage)) : std::string(stageName(stage)) + ": " + detail;
}

std::vector<StageTiming> StepPlan::timings() const
{
  std::vector<StageTiming> result;
  result.reserve(Order.size());
  for (Stage stage : Order)
  {
    result.push_back({ stage, label(stage), seconds(stage) });
  }
  return result;
}

std::vector<std::string> StepPlan::labels() const
{
  std::vector<std::string> result;
  result.reserve(Order.size());
  for (Stage stage : Order)
  {
    result.push_back(label(stage));
  }
  return result;
}

} // namespace softbody
