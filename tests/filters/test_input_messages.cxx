// filter.input_messages: every doubtful input is answered with a clear error, or a warning that
// says what was done and quotes the user's value:
// - Gmsh hexahedra are split into tets, with a warning counting them, and simulate cleanly;
// - Delaunay 3D's slivers (ParaView's default Sphere) are refused, quoting the worst angle and
//   naming Tetrahedralize Surface (TetGen); so is the remedy for hexahedra in a grid;
// - a Surface far from the body is bound with a warning quoting the distance and the body's
//   size; a Surface that is not polygonal data gets one message naming its type;
// - garbage in a TetGen file is quoted escaped and short, and TetGen prints nothing to stdout.
#include "filter_test_support.h"

#include "vtkDelaunay3D.h"
#include "vtkGmshReader.h"
#include "vtkOutputWindow.h"
#include "vtkPolyData.h"
#include "vtkSoftBodySurfaceInput.h"
#include "vtkSphereSource.h"
#include "vtkTetGenReader.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h> // dup, dup2, getpid

namespace
{
namespace fs = std::filesystem;

/// Collects what VTK sends to its output window (vtkGenericWarningMacro and unobserved messages).
class CapturingOutputWindow : public vtkOutputWindow
{
public:
  static CapturingOutputWindow* New() { return new CapturingOutputWindow; }
  void DisplayText(const char* text) override { this->Text += text ? text : ""; }
  std::string Text;
};

/// The text a callable writes to file descriptor 1 (printf and std::cout alike).
template <typename F>
std::string StdoutOf(F f)
{
  std::cout.flush();
  std::fflush(stdout);
  std::FILE* file = std::tmpfile();
  const int saved = ::dup(1);
  ::dup2(::fileno(file), 1);
  f();
  std::cout.flush();
  std::fflush(stdout);
  ::dup2(saved, 1);
  ::close(saved);
  std::string text;
  std::rewind(file);
  char buffer[512];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0)
    text.append(buffer, n);
  std::fclose(file);
  return text;
}

bool Printable(const std::string& text)
{
  for (const char c : text)
  {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte < 0x20 && c != '\n') || byte >= 0x7f)
      return false;
  }
  return true;
}

bool AnyContains(const std::vector<std::string>& texts, const std::string& fragment)
{
  for (const std::string& t : texts)
    if (t.find(fragment) != std::string::npos)
      return true;
  return false;
}

void GmshHexahedraAreSplitAndSaidSo(const fs::path& dir)
{
  // Two unit cubes side by side (Gmsh 2.2, node order as Gmsh's reference hexahedron).
  const fs::path path = dir / "two_hexes.msh";
  std::ofstream(path) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n12\n"
                         "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n"
                         "9 2 0 0\n10 2 1 0\n11 2 0 1\n12 2 1 1\n$EndNodes\n$Elements\n3\n"
                         "1 3 2 1 1 1 2 3 4\n"
                         "2 5 2 1 1 1 2 3 4 5 6 7 8\n"
                         "3 5 2 1 1 2 9 10 3 6 11 12 7\n$EndElements\n";
  vtkNew<vtkGmshReader> reader;
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(reader);
  reader->SetFileName(path.string().c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  SB_CHECK(messages->Errors.empty(), messages->AllErrors());
  SB_CHECK(grid->GetNumberOfCells() == 12, "2 hexahedra -> 12 tets, got " << grid->GetNumberOfCells());
  SB_CHECK(AnyContains(messages->Warnings, "split 2 hexahedra (Gmsh element type 5) into 12 tetrahedra"),
    "the reader says what it converted; warnings: " << messages->Warnings.size());
  for (const std::string& w : messages->Warnings)
    std::cout << "Gmsh reader warning: " << w << std::endl;

  sbtest::CapturedFilter f(grid);
  SB_CHECK(f.Update(0.05), "the split hexahedra simulate: " << f.Messages->AllErrors());
  SB_CHECK(!AnyContains(f.Messages->Warnings, "belong to no tetrahedron"),
    "no point is left outside every tet");
}

void SliversAndHexahedraAreRefusedNamingTheTetGenFilter()
{
  vtkNew<vtkSphereSource> sphere; // ParaView's default Sphere()
  vtkNew<vtkDelaunay3D> delaunay;
  delaunay->SetInputConnection(sphere->GetOutputPort());
  delaunay->Update();
  for (int method : { 0, 2 })
  {
    sbtest::CapturedFilter f(delaunay->GetOutput());
    f.Filter->SetMethod(method);
    SB_CHECK(!f.Update(0.05), "method " << method << ": Delaunay 3D of a Sphere must be refused");
    const std::string error = f.Messages->AllErrors();
    SB_CHECK(f.Messages->ErrorContains("tetrahedra are slivers") &&
        f.Messages->ErrorContains("the worst is ") &&
        f.Messages->ErrorContains("Tetrahedralize Surface (TetGen)"),
      "method " << method << ": " << error);
    if (method == 0)
      std::cout << "Delaunay 3D sphere: " << error;
  }

  vtkNew<vtkUnstructuredGrid> hexes;
  vtkNew<vtkPoints> points;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        points->InsertNextPoint(i, j, k);
  hexes->SetPoints(points);
  const vtkIdType ids[8] = { 0, 1, 3, 2, 4, 5, 7, 6 };
  hexes->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
  sbtest::CapturedFilter f(hexes);
  SB_CHECK(!f.Update(0.05), "a hexahedron is refused");
  SB_CHECK(f.Messages->ErrorContains("1 vtkHexahedron") &&
      f.Messages->ErrorContains("Tetrahedralize Surface (TetGen)") &&
      !f.Messages->ErrorContains("Delaunay"),
    f.Messages->AllErrors());
}

void FarSurfaceWarnsAndWrongTypeIsOneError(CapturingOutputWindow* window)
{
  auto body = sbtest::MakeTetBox(2, 2, 2, 0.1, { 0.0, 0.0, 0.0 }); // 0.2 m cube, diagonal 0.346 m
  vtkNew<vtkSphereSource> near;
  near->SetCenter(0.1, 0.1, 0.1);
  near->SetRadius(0.1);
  near->Update();
  {
    window->Text.clear();
    sbtest::CapturedFilter f(body);
    f.Filter->SetInputData(1, near->GetOutput());
    SB_CHECK(f.Update(0.05), f.Messages->AllErrors());
    SB_CHECK(window->Text.find("Surface input lies") == std::string::npos,
      "a surface on the body gives no warning: " << window->Text);
  }
  vtkNew<vtkSphereSource> far;
  far->SetCenter(14.0, 0.1, 0.1);
  far->SetRadius(0.1);
  far->Update();
  {
    window->Text.clear();
    sbtest::CapturedFilter f(body);
    f.Filter->SetInputData(1, far->GetOutput());
    SB_CHECK(f.Update(0.05), f.Messages->AllErrors());
    SB_CHECK(window->Text.find("The Surface input lies up to 13.9 m outside the body's bounding "
                               "box, whose diagonal (the body's size) is 0.346 m") != std::string::npos,
      "warning quoting distance and size expected: " << window->Text);
    std::cout << "far Surface: " << window->Text << std::endl;
    const std::size_t once = window->Text.size();
    SB_CHECK(f.Update(0.1), f.Messages->AllErrors());
    SB_CHECK(window->Text.size() == once, "said once per binding, not every frame");
    SB_CHECK(sbtest::FieldString(f.Mesh(), "Warnings").find("Surface input lies") != std::string::npos,
      "the far-surface warning is also in field data Warnings");
  }
  {
    // A grid connected as the Surface: exactly one error, naming its type and the remedy.
    sbtest::CapturedFilter f(body);
    f.Filter->SetInputData(1, body);
    SB_CHECK(!f.Update(0.05), "a vtkUnstructuredGrid Surface is refused");
    std::size_t count = 0;
    for (const std::string& error : f.Messages->Errors)
    {
      count += error.find("must be a polygonal surface (vtkPolyData); it is a vtkUnstructuredGrid") !=
          std::string::npos ? 1 : 0;
    }
    SB_CHECK(count == 1, "one clear error expected; got:\n" << f.Messages->AllErrors());
    SB_CHECK(f.Messages->Errors.size() <= 2,
      "no repeated type errors (the executive may add one 'returned failure'); got:\n"
        << f.Messages->AllErrors());
  }

  // The check the filter's Surface port calls (see vtkSoftBodySurfaceInput::SkinSurfaceError).
  SB_CHECK(vtkSoftBodySurfaceInput::SkinSurfaceError(nullptr).empty(), "no surface is fine");
  SB_CHECK(vtkSoftBodySurfaceInput::SkinSurfaceError(far->GetOutput()).empty(), "polydata is fine");
  const std::string wrong = vtkSoftBodySurfaceInput::SkinSurfaceError(body);
  SB_CHECK(wrong == "The Surface input must be a polygonal surface (vtkPolyData); it is a "
                    "vtkUnstructuredGrid. To skin it onto the body, apply Extract Surface to it first.",
    wrong);
}

void TetGenGarbageIsQuotedSafelyAndTetGenIsSilent(const fs::path& dir)
{
  // A valid mesh: TetGen's loader prints "Opening ..." for each file; none of it may reach stdout.
  std::ofstream(dir / "tet.node") << "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  std::ofstream(dir / "tet.ele") << "1 4 0\n1 1 2 3 4\n";
  vtkNew<vtkTetGenReader> reader;
  vtkNew<sbtest::MessageCatcher> messages;
  messages->Observe(reader);
  messages->Observe(reader->GetExecutive());
  reader->SetFileName((dir / "tet.node").string().c_str());
  const std::string printed = StdoutOf([&] { reader->Update(); });
  SB_CHECK(messages->Errors.empty(), messages->AllErrors());
  SB_CHECK(reader->GetOutput()->GetNumberOfCells() == 1, "one tet read");
  SB_CHECK(printed.empty(), "TetGen printed to stdout: '" << printed << "'");

  // Binary garbage in the header: quoted escaped and short.
  std::string junk = "4 3 \x01\x02\xff\xfe\x1b[2J";
  for (int i = 0; i < 300; ++i)
    junk += static_cast<char>(0x80 + i % 100);
  std::ofstream(dir / "junk.node", std::ios::binary) << junk << "\n1 0 0 0\n";
  std::ofstream(dir / "junk.ele") << "1 4 0\n1 1 2 3 4\n";
  vtkNew<vtkTetGenReader> bad;
  vtkNew<sbtest::MessageCatcher> badMessages;
  badMessages->Observe(bad);
  badMessages->Observe(bad->GetExecutive());
  bad->SetFileName((dir / "junk.node").string().c_str());
  const std::string badPrinted = StdoutOf([&] { bad->Update(); });
  const std::string error = badMessages->Errors.empty() ? "" : badMessages->Errors.front();
  SB_CHECK(!error.empty(), "garbage is an error");
  SB_CHECK(Printable(error), "only printable characters in: " << error);
  SB_CHECK(error.find("\\x01\\x02\\xFF\\xFE\\x1B[2J") != std::string::npos, error);
  SB_CHECK(error.size() < 400, "short: " << error.size() << " characters");
  SB_CHECK(badPrinted.empty(), "nothing on stdout: '" << badPrinted << "'");
  std::cout << "TetGen garbage: " << error << std::endl;
}
} // namespace

int main()
{
  const fs::path dir =
    fs::temp_directory_path() / ("softbody_input_messages_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  vtkNew<CapturingOutputWindow> window;
  vtkOutputWindow::SetInstance(window);

  GmshHexahedraAreSplitAndSaidSo(dir);
  SliversAndHexahedraAreRefusedNamingTheTetGenFilter();
  FarSurfaceWarnsAndWrongTypeIsOneError(window);
  TetGenGarbageIsQuotedSafelyAndTetGenIsSilent(dir);

  vtkOutputWindow::SetInstance(nullptr);
  fs::remove_all(dir);
  return sbtest::Result("filter.input_messages");
}
