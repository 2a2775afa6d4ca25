// Helpers shared by the filter tests: a tetrahedral box built with plain VTK, an observer
// that captures error and warning messages, and a CHECK macro that counts failures.
//
// The tests are plain programs (exit code 0 = pass) driving vtkSoftBodyFilter through
// UpdateTimeStep, as ParaView's pipeline does; no ServerManager or Python involved.
#pragma once

#include "vtkSoftBodyFilter.h"
#include "vtkSoftBodyOutputPort.h"

#include "vtkCellType.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace sbtest
{

inline int& FailureCount()
{
  static int count = 0;
  return count;
}

#define SB_CHECK(condition, message)                                                               \
  do                                                                                               \
  {                                                                                                \
    if (!(condition))                                                                              \
    {                                                                                              \
      std::cerr << __FILE__ << ":" << __LINE__ << ": FAILED: " #condition " -- " << message      \
                << std::endl;                                                                      \
      ++sbtest::FailureCount();                                                                    \
    }                                                                                              \
  } while (false)

/// The first value of a string field-data array, or "(missing)".
inline std::string FieldString(vtkDataObject* data, const char* name)
{
  auto* array = vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name));
  return array && array->GetNumberOfValues() > 0 ? array->GetValue(0) : std::string("(missing)");
}

/// Exit code for main(): 0 when every check passed.
inline int Result(const char* testName)
{
  if (FailureCount() == 0)
  {
    std::cout << testName << ": all checks passed" << std::endl;
    return 0;
  }
  std::cerr << testName << ": " << FailureCount() << " check(s) failed" << std::endl;
  return 1;
}

/// Signed volume of a tet, (p1-p0) . ((p2-p0) x (p3-p0)) / 6.
inline double TetVolume(const double p0[3], const double p1[3], const double p2[3], const double p3[3])
{
  double a[3], b[3], c[3];
  for (int i = 0; i < 3; ++i)
  {
    a[i] = p1[i] - p0[i];
    b[i] = p2[i] - p0[i];
    c[i] = p3[i] - p0[i];
  }
  return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0])) /
    6.0;
}

/// A box of nx*ny*nz cubes of edge `h` starting at `origin`, each cube split into the 6 Kuhn
/// tetrahedra (all positively oriented), as float points like many readers produce.
inline vtkSmartPointer<vtkUnstructuredGrid> MakeTetBox(
  int nx, int ny, int nz, double h, std::array<double, 3> origin)
{
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  auto index = [&](int i, int j, int k) { return vtkIdType(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
  {
    for (int j = 0; j <= ny; ++j)
    {
      for (int i = 0; i <= nx; ++i)
      {
        points->InsertNextPoint(origin[0] + i * h, origin[1] + j * h, origin[2] + k * h);
      }
    }
  }
  grid->SetPoints(points);
  grid->Allocate(vtkIdType(6) * nx * ny * nz);
  // Each axis order walks from corner (0,0,0) to (1,1,1) one axis at a time: one Kuhn tet.
  const int orders[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
    { 2, 1, 0 } };
  for (int k = 0; k < nz; ++k)
  {
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        for (const auto& order : orders)
        {
          int c[3] = { 0, 0, 0 };
          vtkIdType ids[4];
          ids[0] = index(i, j, k);
          for (int s = 0; s < 3; ++s)
          {
            c[order[s]] = 1;
            ids[s + 1] = index(i + c[0], j + c[1], k + c[2]);
          }
          double p[4][3];
          for (int v = 0; v < 4; ++v)
          {
            points->GetPoint(ids[v], p[v]);
          }
          if (TetVolume(p[0], p[1], p[2], p[3]) < 0.0)
          {
            std::swap(ids[2], ids[3]);
          }
          grid->InsertNextCell(VTK_TETRA, 4, ids);
        }
      }
    }
  }
  return grid;
}

/// Collects the messages of ErrorEvent and WarningEvent. While it observes an object, VTK
/// hands the messages to it instead of printing them.
class MessageCatcher : public vtkCommand
{
public:
  static MessageCatcher* New() { return new MessageCatcher; }

  void Execute(vtkObject*, unsigned long event, void* callData) override
  {
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings).push_back(text);
  }

  void Observe(vtkObject* object)
  {
    object->AddObserver(vtkCommand::ErrorEvent, this);
    object->AddObserver(vtkCommand::WarningEvent, this);
  }

  void Clear()
  {
    this->Errors.clear();
    this->Warnings.clear();
  }

  std::string AllErrors() const
  {
    std::string all;
    for (const std::string& e : this->Errors)
    {
      all += e + "\n";
    }
    return all;
  }

  bool ErrorContains(const std::string& fragment) const
  {
    return this->AllErrors().find(fragment) != std::string::npos;
  }

  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;
};

/// A filter with its messages (and its executive's "returned failure" messages) captured.
struct CapturedFilter
{
  vtkNew<vtkSoftBodyFilter> Filter;
  vtkNew<MessageCatcher> Messages;

  explicit CapturedFilter(vtkUnstructuredGrid* input)
  {
    this->Filter->SetInputData(input);
    this->Messages->Observe(this->Filter);
    this->Messages->Observe(this->Filter->GetExecutive());
  }

  /// Updates at time t; returns the pipeline's success flag.
  bool Update(double t) { return this->Filter->UpdateTimeStep(t) != 0; }

  vtkUnstructuredGrid* Mesh() { return vtkUnstructuredGrid::SafeDownCast(this->Filter->GetOutput(vtkSoftBodyPortNumber(vtkSoftBodyOutputPort::Mesh))); }
};

/// The points of a data set as doubles, for bitwise comparisons.
inline std::vector<double> PointsOf(vtkPointSet* data)
{
  std::vector<double> xyz;
  if (!data || !data->GetPoints())
  {
    return xyz;
  }
  xyz.resize(3 * static_cast<std::size_t>(data->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
  {
    data->GetPoint(i, &xyz[3 * static_cast<std::size_t>(i)]);
  }
  return xyz;
}

inline bool BitwiseEqual(const std::vector<double>& a, const std::vector<double>& b)
{
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// First value of a numeric field-data array, or NaN when absent.
inline double FieldValue(vtkDataObject* data, const char* name)
{
  vtkDataArray* array = data ? data->GetFieldData()->GetArray(name) : nullptr;
  return (array && array->GetNumberOfTuples() > 0) ? array->GetTuple1(0) : std::nan("");
}

inline std::vector<std::string> FieldStrings(vtkDataObject* data, const char* name)
{
  std::vector<std::string> values;
  vtkStringArray* array =
    data ? vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name)) : nullptr;
  for (vtkIdType i = 0; array && i < array->GetNumberOfValues(); ++i)
  {
    values.push_back(array->GetValue(i));
  }
  return values;
}

} // namespace sbtest
