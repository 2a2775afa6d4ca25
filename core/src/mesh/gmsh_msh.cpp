// Gmsh .msh ASCII reader (formats 2.x and 4.1): nodes and 4-node tetrahedra only.
//
// Why our own reader rather than the Gmsh API (libgmsh-dev): the API is one global,
// non-thread-safe session (gmsh::initialize/open/finalize) that would be shared with anything
// else in the ParaView process; it prints, and its error paths may call exit() unless
// configured otherwise; it is a large dependency (OpenCASCADE, FLTK, ...) for what here is two
// sections of a text format. A small reader that checks every line can report truncated and
// garbled files with a line number and never take the process down.
//
// The reader is line-based, as Gmsh writes ASCII files: one node or element per line
// (4.1: node tags and coordinates on separate lines). Counts in section headers are checked
// against what follows, so a garbled count cannot make it allocate or loop without end.
#include "softbody/mesh/mesh_io.h"

#include "softbody/common/errors.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <unordered_map>
#include <vector>

namespace softbody
{
namespace
{

class MshParser
{
public:
  MshParser(std::istream& in, const std::string& name)
    : In(in)
    , Name(name)
  {
  }

  TetMesh parse(MeshFileInfo* info);

private:
  std::istream& In;
  std::string Name;
  std::string Line;
  std::size_t LineNumber = 0;
  std::vector<std::string_view> Tokens;
  bool Version4 = false;
  bool SeenNodes = false, SeenElements = false;
  std::unordered_map<long long, std::int32_t> NodeIndex;
  TetMesh Mesh;
  std::size_t Skipped = 0;

  [[noreturn]] void fail(const std::string& what) const
  {
    throw InvalidInputError(
      this->Name + ":" + std::to_string(this->LineNumber) + ": " + what);
  }

  /// Next line (without '\r'); false at end of file.
  bool next()
  {
    if (!std::getline(this->In, this->Line))
    {
      return false;
    }
    ++this->LineNumber;
    if (!this->Line.empty() && this->Line.back() == '\r')
    {
      this->Line.pop_back();
    }
    return true;
  }

  void require(const char* context)
  {
    if (!this->next())
    {
      this->fail(std::string("unexpected end of file in ") + context + " (truncated file?).");
    }
  }

  /// Splits the current line on blanks into Tokens.
  void tokenize()
  {
    this->Tokens.clear();
    const std::string& s = this->Line;
    std::size_t i = 0;
    while (i < s.size())
    {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t'))
        ++i;
      const std::size_t start = i;
      while (i < s.size() && s[i] != ' ' && s[i] != '\t')
        ++i;
      if (i > start)
        this->Tokens.emplace_back(s.data() + start, i - start);
    }
  }

  /// Next line as exactly `count` tokens (or at least, when atLeast).
  void requireTokens(const char* context, std::size_t count, bool atLeast = false)
  {
    this->require(context);
    this->tokenize();
    if (this->Tokens.size() < count || (!atLeast && this->Tokens.size() != count))
    {
      this->fail(std::string("expected ") + (atLeast ? "at least " : "") + std::to_string(count) +
        " numbers in " + context + ", found " + std::to_string(this->Tokens.size()) + ": '" +
        this->Line.substr(0, 80) + "'.");
    }
  }

  long long integer(std::size_t i, const char* what) const
  {
    const std::string_view t = this->Tokens[i];
    long long v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
    {
      this->fail(std::string("expected an integer ") + what + ", found '" + std::string(t) + "'.");
    }
    return v;
  }

  /// A count from a header, bounded so that a garbled value is an error, not a huge allocation.
  std::size_t count(std::size_t i, const char* what) const
  {
    const long long v = this->integer(i, what);
    if (v < 0 || v > (1LL << 31) - 1)
    {
      this->fail(std::string("invalid ") + what + " " + std::to_string(v) + ".");
    }
    return static_cast<std::size_t>(v);
  }

  double real(std::size_t i) const
  {
    const std::string_view t = this->Tokens[i];
    double v = 0.0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v))
    {
      this->fail("expected a finite coordinate, found '" + std::string(t) + "'.");
    }
    return v;
  }

  void addNode(long long tag, const Vec3& p)
  {
    const auto index = static_cast<std::int32_t>(this->Mesh.points.size());
    if (!this->NodeIndex.emplace(tag, index).second)
    {
      this->fail("node tag " + std::to_string(tag) + " appears twice.");
    }
    this->Mesh.points.push_back(p);
  }

  void addTet(std::size_t firstNodeToken)
  {
    Tet tet;
    for (int c = 0; c < 4; ++c)
    {
      const long long tag = this->integer(firstNodeToken + c, "node tag");
      const auto it = this->NodeIndex.find(tag);
      if (it == this->NodeIndex.end())
      {
        this->fail("tetrahedron names node " + std::to_string(tag) + ", which is not in $Nodes.");
      }
      tet[c] = it->second;
    }
    this->Mesh.tets.push_back(tet);
  }

  void expectEnd(const char* endTag)
  {
    this->require(endTag);
    if (this->Line.rfind(endTag, 0) != 0)
    {
      this->fail(std::string("expected ") + endTag + ", found '" + this->Line.substr(0, 80) +
        "' (a count in the section header does not match its content?).");
    }
  }

  void readFormat();
  void readNodes2();
  void readElements2();
  void readNodes4();
  void readElements4();
  void skipSection(const std::string& name);
};

void MshParser::readFormat()
{
  this->requireTokens("$MeshFormat", 3, true);
  const std::string version(this->Tokens[0]);
  const long long fileType = this->integer(1, "file type");
  if (fileType != 0)
  {
    this->fail("binary .msh files are not supported; save the mesh as ASCII in Gmsh "
               "(File > Export, 'Save all elements', ASCII format 4.1 or 2.2).");
  }
  if (version.rfind("2.", 0) == 0)
  {
    this->Version4 = false;
  }
  else if (version == "4.1")
  {
    this->Version4 = true;
  }
  else
  {
    this->fail("unsupported .msh format version '" + version + "'; ASCII 2.2 and 4.1 are read.");
  }
  this->expectEnd("$EndMeshFormat");
}

void MshParser::readNodes2()
{
  this->requireTokens("$Nodes header", 1);
  const std::size_t n = this->count(0, "node count");
  this->Mesh.points.reserve(std::min<std::size_t>(n, 1u << 20));
  for (std::size_t i = 0; i < n; ++i)
  {
    this->requireTokens("a node line (tag x y z)", 4);
    this->addNode(this->integer(0, "node tag"), Vec3(this->real(1), this->real(2), this->real(3)));
  }
  this->expectEnd("$EndNodes");
}

void MshParser::readElements2()
{
  this->requireTokens("$Elements header", 1);
  const std::size_t n = this->count(0, "element count");
  for (std::size_t i = 0; i < n; ++i)
  {
    // tag type number-of-tags tag... node...
    this->requireTokens("an element line (tag type ntags ...)", 3, true);
    const long long type = this->integer(1, "element type");
    const std::size_t tags = this->count(2, "number of element tags");
    if (type != 4)
    {
      ++this->Skipped;
      continue;
    }
    if (this->Tokens.size() != 3 + tags + 4)
    {
      this->fail("a tetrahedron (type 4) needs " + std::to_string(tags) + " tags and 4 nodes, "
        "the line has " + std::to_string(this->Tokens.size()) + " numbers.");
    }
    this->integer(0, "element tag");
    this->addTet(3 + tags);
  }
  this->expectEnd("$EndElements");
}

void MshParser::readNodes4()
{
  // numEntityBlocks numNodes minNodeTag maxNodeTag, then per block:
  // entityDim entityTag parametric numNodesInBlock; the tags, one a line; the coordinates.
  this->requireTokens("$Nodes header", 4);
  const std::size_t blocks = this->count(0, "entity block count");
  const std::size_t total = this->count(1, "node count");
  this->Mesh.points.reserve(std::min<std::size_t>(total, 1u << 20));
  std::vector<long long> tags;
  for (std::size_t b = 0; b < blocks; ++b)
  {
    this->requireTokens("a node block header", 4);
    const long long dim = this->integer(0, "entity dimension");
    const long long parametric = this->integer(2, "parametric flag");
    const std::size_t n = this->count(3, "number of nodes in block");
    if (dim < 0 || dim > 3 || (parametric != 0 && parametric != 1))
    {
      this->fail("invalid node block header '" + this->Line.substr(0, 80) + "'.");
    }
    if (this->Mesh.points.size() + n > total)
    {
      this->fail("the node blocks hold more nodes than the $Nodes header's " +
        std::to_string(total) + ".");
    }
    tags.clear();
    for (std::size_t i = 0; i < n; ++i)
    {
      this->requireTokens("a node tag", 1);
      tags.push_back(this->integer(0, "node tag"));
    }
    // Parametric nodes carry dim extra parametric coordinates after x y z.
    const std::size_t width = 3 + (parametric ? static_cast<std::size_t>(dim) : 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      this->requireTokens("node coordinates", width);
      this->addNode(tags[i], Vec3(this->real(0), this->real(1), this->real(2)));
    }
  }
  if (this->Mesh.points.size() != total)
  {
    this->fail("the $Nodes header announces " + std::to_string(total) + " nodes, the blocks hold " +
      std::to_string(this->Mesh.points.size()) + ".");
  }
  this->expectEnd("$EndNodes");
}

void MshParser::readElements4()
{
  // numEntityBlocks numElements minTag maxTag, then per block:
  // entityDim entityTag elementType numElementsInBlock; one element a line: tag node...
  this->requireTokens("$Elements header", 4);
  const std::size_t blocks = this->count(0, "entity block count");
  const std::size_t total = this->count(1, "element count");
  std::size_t seen = 0;
  for (std::size_t b = 0; b < blocks; ++b)
  {
    this->requireTokens("an element block header", 4);
    const long long type = this->integer(2, "element type");
    const std::size_t n = this->count(3, "number of elements in block");
    if (seen + n > total)
    {
      this->fail("the element blocks hold more elements than the $Elements header's " +
        std::to_string(total) + ".");
    }
    seen += n;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (type != 4)
      {
        this->requireTokens("an element line", 2, true);
        ++this->Skipped;
        continue;
      }
      this->requireTokens("a tetrahedron line (tag n1 n2 n3 n4)", 5);
      this->integer(0, "element tag");
      this->addTet(1);
    }
  }
  if (seen != total)
  {
    this->fail("the $Elements header announces " + std::to_string(total) +
      " elements, the blocks hold " + std::to_string(seen) + ".");
  }
  this->expectEnd("$EndElements");
}

void MshParser::skipSection(const std::string& name)
{
  // $PhysicalNames, $Entities, $NodeData, ...: not needed for the tets; skipped to their end.
  const std::string endTag = "$End" + name.substr(1);
  const std::size_t start = this->LineNumber;
  while (this->next())
  {
    if (this->Line.rfind(endTag, 0) == 0)
    {
      return;
    }
  }
  this->LineNumber = start;
  this->fail("section " + name + " has no " + endTag + " (truncated file?).");
}

TetMesh MshParser::parse(MeshFileInfo* info)
{
  bool seenFormat = false;
  while (this->next())
  {
    this->tokenize();
    if (this->Tokens.empty())
    {
      continue;
    }
    const std::string section(this->Tokens[0]);
    if (section.empty() || section[0] != '$')
    {
      this->fail("expected a section such as $Nodes, found '" + this->Line.substr(0, 80) +
        "' (not a Gmsh .msh file, or garbled).");
    }
    if (!seenFormat && section != "$MeshFormat")
    {
      this->fail("a .msh file starts with $MeshFormat, found '" + section + "'.");
    }
    if (section == "$MeshFormat")
    {
      if (seenFormat)
        this->fail("$MeshFormat appears twice.");
      this->readFormat();
      seenFormat = true;
    }
    else if (section == "$Nodes")
    {
      if (this->SeenNodes)
        this->fail("$Nodes appears twice.");
      this->Version4 ? this->readNodes4() : this->readNodes2();
      this->SeenNodes = true;
    }
    else if (section == "$Elements")
    {
      if (!this->SeenNodes)
        this->fail("$Elements before $Nodes.");
      if (this->SeenElements)
        this->fail("$Elements appears twice.");
      this->Version4 ? this->readElements4() : this->readElements2();
      this->SeenElements = true;
    }
    else if (section.rfind("$End", 0) == 0)
    {
      this->fail("unexpected " + section + " outside its section.");
    }
    else
    {
      this->skipSection(section);
    }
  }
  if (!seenFormat)
  {
    this->fail("empty file: no $MeshFormat section.");
  }
  if (!this->SeenNodes || !this->SeenElements)
  {
    this->fail(std::string("no ") + (this->SeenNodes ? "$Elements" : "$Nodes") +
      " section (truncated file?).");
  }
  if (this->Mesh.tets.empty())
  {
    this->fail("the mesh holds no tetrahedra (element type 4; " + std::to_string(this->Skipped) +
      " other elements skipped). Generate a 3-D mesh in Gmsh (Mesh > 3D).");
  }
  if (info)
  {
    info->format = this->Version4 ? "Gmsh 4.1" : "Gmsh 2.2";
    info->skippedElements = this->Skipped;
  }
  return std::move(this->Mesh);
}

} // namespace

TetMesh readGmshMesh(std::istream& in, const std::string& name, MeshFileInfo* info)
{
  return MshParser(in, name).parse(info);
}

TetMesh readGmshMesh(const std::string& path, MeshFileInfo* info)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    throw InvalidInputError("Cannot open Gmsh file '" + path + "'.");
  }
  return readGmshMesh(in, path, info);
}

} // namespace softbody
