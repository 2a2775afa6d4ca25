// TetGen .node/.ele through TetGen's own loaders (tetgenio::load_node / load_tet), so the files
// are read exactly as TetGen reads them. Its loaders trust their input (a garbled count makes
// them allocate or read blindly, and they print to stdout), so the headers are checked here
// first against what the file really holds, and the loaded arrays are checked afterwards.
// What they print ("Opening ...", and their own error reports) is captured, never left on the
// process's stdout: on failure it becomes part of the error message.
#include "softbody/mesh/mesh_io.h"

#include "softbody/common/errors.h"

#include <tetgen.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <sstream>
#include <string_view>
#include <vector>

#include <unistd.h> // dup, dup2: TetGen's loaders printf to stdout

namespace softbody
{
namespace
{

/// Redirects file descriptor 1 into a temporary file for its lifetime and gives back what was
/// written. TetGen's loaders call printf; its text would otherwise end up in the middle of a
/// benchmark's output or ParaView's console. Process-wide, as stdout is: another thread's
/// printf during a load is captured too (loads are short). If the redirection cannot be set
/// up, the output simply stays on stdout.
class StdoutCapture
{
public:
  StdoutCapture()
  {
    std::fflush(stdout);
    this->File = std::tmpfile();
    if (this->File)
    {
      this->Saved = ::dup(1);
      if (this->Saved < 0 || ::dup2(::fileno(this->File), 1) < 0)
      {
        this->restore();
      }
    }
  }
  ~StdoutCapture()
  {
    this->restore();
    if (this->File)
    {
      std::fclose(this->File);
    }
  }
  StdoutCapture(const StdoutCapture&) = delete;
  StdoutCapture& operator=(const StdoutCapture&) = delete;

  /// Ends the capture and returns the captured text.
  std::string finish()
  {
    this->restore();
    std::string text;
    if (this->File && std::fseek(this->File, 0, SEEK_SET) == 0)
    {
      char buffer[4096];
      std::size_t n = 0;
      while ((n = std::fread(buffer, 1, sizeof buffer, this->File)) > 0 && text.size() < (1u << 16))
      {
        text.append(buffer, n);
      }
    }
    return text;
  }

private:
  void restore()
  {
    if (this->Saved >= 0)
    {
      std::fflush(stdout);
      ::dup2(this->Saved, 1);
      ::close(this->Saved);
      this->Saved = -1;
    }
  }

  std::FILE* File = nullptr;
  int Saved = -1;
};

/// TetGen's report for a message: its lines joined, without the "Opening ..." lines.
std::string tetgenReport(const std::string& captured)
{
  std::string report;
  std::size_t start = 0;
  while (start < captured.size())
  {
    std::size_t end = captured.find('\n', start);
    if (end == std::string::npos)
      end = captured.size();
    const std::string line = captured.substr(start, end - start);
    start = end + 1;
    if (line.empty() || line.rfind("Opening ", 0) == 0)
      continue;
    report += (report.empty() ? "" : " ") + line;
  }
  return report.empty() ? std::string() : " TetGen said: '" + printableExcerpt(report, 120) + "'.";
}

bool endsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Whether TetGen's loaders take this piece of a file as a record. They read with
/// tetgenio::readnumberline: fgets into a buffer of INPUTLINESIZE characters (so a longer line
/// comes in several pieces, each judged alone, and a NUL byte ends what is looked at), then skip
/// every character up to the first one that can start a number ('0'-'9', '.', '+', '-'), a '#'
/// or the end of the string; a piece whose first such character is '#' or the end is skipped.
/// Counting records by any other rule is unsafe: the fuzzer (tests/fuzz/fuzz_tetgen_files)
/// found that a line without any digit (e.g. "@@@" or one starting with a NUL byte) counted as
/// a record here but not by TetGen, so a header that matched our count sent TetGen past the
/// end of the file, where its load_node_call dereferences the NULL line: a SEGV.
bool isTetGenRecord(const char* piece)
{
  for (const char* c = piece; *c != '\0'; ++c)
  {
    if (*c == '#')
      return false;
    if (*c == '.' || *c == '+' || *c == '-' || (*c >= '0' && *c <= '9'))
      return true;
  }
  return false;
}

/// Reads the file in the pieces TetGen's loaders read (see isTetGenRecord), parses the first
/// record as integers and counts the records after it; checks that the header's first number
/// (the count of records) is in [0, records], so TetGen never reads past the end of the file.
std::vector<long long> checkedHeader(const std::string& file, std::size_t expectedFields,
  const char* what, std::size_t& dataLines)
{
  std::FILE* in = std::fopen(file.c_str(), "rb");
  if (!in)
  {
    throw InvalidInputError("Cannot open TetGen file '" + file + "'.");
  }
  struct Closer
  {
    std::FILE* f;
    ~Closer() { std::fclose(f); }
  } closer{ in };
  std::vector<char> buffer(INPUTLINESIZE);
  std::string line;
  std::vector<long long> header;
  std::size_t lineNumber = 1, headerLine = 0;
  dataLines = 0;
  while (std::fgets(buffer.data(), INPUTLINESIZE, in))
  {
    const std::size_t number = lineNumber;
    line.assign(buffer.data()); // up to a NUL byte, as TetGen sees it
    if (!line.empty() && line.back() == '\n')
    {
      ++lineNumber;
    }
    if (!isTetGenRecord(buffer.data()))
    {
      continue;
    }
    if (headerLine == 0)
    {
      headerLine = number;
      // TetGen's load_node reads a .node file whose first record contains "rbox" anywhere as
      // a qhull rbox file: the dimension first, then the point count on the next record, which
      // the check below would not bound: "0 # rbox" followed by a count larger than the records
      // left makes TetGen read past the end of the file (a SEGV).
      if (std::string_view(what) == "node" && line.find("rbox") != std::string::npos)
      {
        throw InvalidInputError(file + ":" + std::to_string(number) +
          ": qhull rbox point files are not read; write a TetGen .node header "
          "(<points> 3 <attributes> <markers>).");
      }
      std::istringstream tokens(line.substr(0, line.find('#')));
      std::string token;
      while (tokens >> token)
      {
        char* end = nullptr;
        const long long v = std::strtoll(token.c_str(), &end, 10);
        if (*end != '\0')
        {
          throw InvalidInputError(file + ":" + std::to_string(number) + ": the " + what +
            " header must hold integers, found '" + printableExcerpt(token) + "'.");
        }
        header.push_back(v);
      }
      continue;
    }
    ++dataLines;
  }
  if (headerLine == 0)
  {
    throw InvalidInputError(file + ": empty file, no " + what + " header.");
  }
  const std::string at = file + ":" + std::to_string(headerLine) + ": ";
  if (header.size() < expectedFields)
  {
    throw InvalidInputError(at + "the " + what + " header needs " +
      std::to_string(expectedFields) + " numbers, found " + std::to_string(header.size()) + ".");
  }
  if (header[0] < 0 || static_cast<unsigned long long>(header[0]) > dataLines)
  {
    throw InvalidInputError(at + "the header announces " + std::to_string(header[0]) + " " +
      what + " records but the file holds " + std::to_string(dataLines) +
      " data lines (truncated file?).");
  }
  for (std::size_t i = 1; i < header.size(); ++i)
  {
    if (header[i] < 0 || header[i] > 1000)
    {
      throw InvalidInputError(
        at + "implausible " + what + " header value " + std::to_string(header[i]) + ".");
    }
  }
  return header;
}

} // namespace

TetMesh readTetGenMesh(const std::string& path, MeshFileInfo* info)
{
  std::string base = path;
  if (endsWith(base, ".node"))
  {
    base.resize(base.size() - 5);
  }
  else if (endsWith(base, ".ele"))
  {
    base.resize(base.size() - 4);
  }
  const std::string nodeFile = base + ".node", eleFile = base + ".ele";
  // TetGen copies the name into a fixed buffer of FILENAMESIZE (1024) characters.
  if (base.size() + 8 >= 1024)
  {
    throw InvalidInputError("TetGen file name too long (TetGen's limit is 1024 characters): " + path);
  }

  std::size_t nodeLines = 0, eleLines = 0;
  const std::vector<long long> nodeHeader = checkedHeader(nodeFile, 1, "node", nodeLines);
  if (nodeHeader.size() >= 2 && nodeHeader[1] != 3)
  {
    throw InvalidInputError(nodeFile + ": only 3-D meshes are supported (dimension " +
      std::to_string(nodeHeader[1]) + ").");
  }
  const std::vector<long long> eleHeader = checkedHeader(eleFile, 1, "element", eleLines);
  if (eleHeader.size() >= 2 && eleHeader[1] != 4 && eleHeader[1] != 10)
  {
    throw InvalidInputError(eleFile + ": elements must have 4 (or 10) nodes, the header says " +
      std::to_string(eleHeader[1]) + ".");
  }

  tetgenio io;
  bool loaded = false;
  StdoutCapture capture;
  try
  {
    std::vector<char> name(base.begin(), base.end());
    name.push_back('\0');
    loaded = io.load_node(name.data()) && io.load_tet(name.data());
  }
  catch (int code)
  {
    throw InvalidInputError("TetGen could not read '" + base + ".node/.ele' (error code " +
      std::to_string(code) + "): the file is malformed." + tetgenReport(capture.finish()));
  }
  catch (const std::bad_alloc&)
  {
    throw InvalidInputError("TetGen could not read '" + base + ".node/.ele': out of memory.");
  }
  const std::string report = tetgenReport(capture.finish());
  if (!loaded)
  {
    throw InvalidInputError(
      "TetGen could not read '" + base + ".node/.ele': the file is malformed or truncated." + report);
  }
  if (io.mesh_dim != 3 || io.numberofpoints <= 0 || !io.pointlist)
  {
    throw InvalidInputError(nodeFile + ": no 3-D points.");
  }
  if (io.numberoftetrahedra <= 0 || !io.tetrahedronlist || io.numberofcorners < 4)
  {
    throw InvalidInputError(eleFile + ": no tetrahedra.");
  }

  TetMesh mesh;
  mesh.points.resize(static_cast<std::size_t>(io.numberofpoints));
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    mesh.points[i] = Vec3(io.pointlist[3 * i], io.pointlist[3 * i + 1], io.pointlist[3 * i + 2]);
    if (!mesh.points[i].allFinite())
    {
      throw InvalidInputError(
        nodeFile + ": point " + std::to_string(i + io.firstnumber) + " has a non-finite coordinate.");
    }
  }
  mesh.tets.resize(static_cast<std::size_t>(io.numberoftetrahedra));
  const auto stride = static_cast<std::size_t>(io.numberofcorners);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
  {
    for (int c = 0; c < 4; ++c)
    {
      // Indices in the file count from the first point's number (0 or 1).
      const long long v = static_cast<long long>(io.tetrahedronlist[stride * t + c]) - io.firstnumber;
      if (v < 0 || v >= io.numberofpoints)
      {
        throw InvalidInputError(eleFile + ": element " + std::to_string(t + io.firstnumber) +
          " names point " + std::to_string(v + io.firstnumber) + ", which does not exist.");
      }
      mesh.tets[t][c] = static_cast<std::int32_t>(v);
    }
  }
  if (info)
  {
    info->format = "TetGen";
    info->skippedElements = 0;
  }
  return mesh;
}

} // namespace softbody
