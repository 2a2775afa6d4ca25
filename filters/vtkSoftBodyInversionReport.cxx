#include "vtkSoftBodyInversionReport.h"

#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>

#include <sstream>

//------------------------------------------------------------------------------
std::size_t vtkSoftBodyInversionReport::Count(
  const std::vector<double>& ratios, const softbody::PbdSimulation* pbd)
{
  std::size_t inverted = 0;
  for (std::size_t t = 0; t < ratios.size(); ++t)
  {
    inverted += ratios[t] <= 0.0 && !(pbd && pbd->tetBroken(t)) ? 1 : 0;
  }
  return inverted;
}

//------------------------------------------------------------------------------
void vtkSoftBodyInversionReport::AddField(std::size_t inverted, vtkFieldData* field)
{
  vtkNew<vtkIdTypeArray> count;
  count->SetName("InvertedTets");
  count->InsertNextValue(static_cast<vtkIdType>(inverted));
  field->AddArray(count);
}

//------------------------------------------------------------------------------
std::string vtkSoftBodyInversionReport::Warning(std::size_t inverted, std::size_t tets, double time,
  const vtkSoftBodyFilter::Parameters& p)
{
  if (inverted == 0)
  {
    return {};
  }
  std::ostringstream text;
  text << inverted << " of " << tets << " tets are inverted at t = " << time
       << " s (VolumeRatio <= 0; field data InvertedTets counts them in every frame). ";
  if (p.Method == vtkSoftBodyFilter::MASS_SPRING && p.MaterialModel != vtkSoftBodyFilter::SPRING_NETWORK)
  {
    text << "The finite-element material pushes inverted tets back, but a step that crushes them "
            "faster than they recover leaves them inverted; the implicit integrators resolve "
            "contacts with obstacles and other bodies only after each step (TimeStep "
         << p.TimeStep << " s; 0 = one step per frame): lower TimeStep, or use Euler-Cromer for "
            "bodies that touch.";
  }
  else if (p.Method == vtkSoftBodyFilter::MASS_SPRING)
  {
    text << "Mass-Spring's springs and linear volume term do not keep a tet from turning inside "
            "out when the load on it is large against YoungsModulus ("
         << p.YoungsModulus << " Pa): raise YoungsModulus, or use XPBD, whose volume projection "
            "has a least volume.";
  }
  else
  {
    text << (p.Method == vtkSoftBodyFilter::PBD ? "PBD" : "XPBD") << " with Iterations "
         << p.Iterations << " x Substeps " << p.Substeps
         << " has not converged where the body is loaded: a resting or pressed body's support "
            "reaches up through it over the iterations, and small tets near the contact are "
            "crushed meanwhile. Raise Substeps (4 leave none on the resting ellipsoid of the "
            "floor tests) or Iterations.";
  }
  return text.str();
}
