// Gmsh .msh ASCII reader (formats 2.x and 4.1): nodes, 4-node tetrahedra, and 8-node hexahedra,
// 6-node prisms and 5-node pyramids split into tetrahedra.
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

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace softbody
{
namespace
{

/// A linear volume cell other than the tet, in Gmsh's node order, with its faces listed
/// counter-clockwise seen from outside (worked out from Gmsh's reference elements).
struct CellShape
{
  int type;          ///< Gmsh element type
  const char* name;  ///< plural, for messages
  const char* one;   ///< singular
  int nodes;
  int tetsPerCell;   ///< what the split below makes
  std::vector<std::vector<int>> faces;
};

const std::vector<CellShape>& splitShapes()
{
  static const std::vector<CellShape> shapes = {
    { 5, "hexahedra", "hexahedron", 8, 6,
      { { 0, 3, 2, 1 }, { 4, 5, 6, 7 }, { 0, 1, 5, 4 }, { 1, 2, 6, 5 }, { 2, 3, 7, 6 },
        { 3, 0, 4, 7 } } },
    { 6, "prisms", "prism", 6, 3, { { 0, 2, 1 }, { 3, 4, 5 }, { 0, 1, 4, 3 }, { 0, 3, 5, 2 }, { 1, 2, 5, 4 } } },
    { 7, "pyramids", "pyramid", 5, 2, { { 0, 3, 2, 1 }, { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 }, { 3, 0, 4 } } },
  };
  return shapes;
}

const CellShape* splitShapeOf(long long type)
{
  for (const CellShape& shape : splitShapes())
  {
    if (shape.type == type)
    {
      return &shape;
    }
  }
  return nullptr;
}

/// Volume cells of order 2 and higher (tetrahedra, hexahedra, prisms, pyramids): refused, since
/// dropping their edge and face nodes would leave points in no cell. Name, or nullptr.
const char* higherOrderVolumeName(long long type)
{
  switch (type)
  {
    case 11: return "10-node tetrahedra";
    case 12: return "27-node hexahedra";
    case 13: return "18-node prisms";
    case 14: return "14-node pyramids";
    case 17: return "20-node hexahedra";
    case 18: return "15-node prisms";
    case 19: return "13-node pyramids";
    case 29: return "20-node tetrahedra";
    case 30: return "35-node tetrahedra";
    case 31: return "56-node tetrahedra";
    case 92: return "64-node hexahedra";
    case 93: return "125-node hexahedra";
    default: return nullptr;
  }
}

/// Splits a convex cell into tets by "pulling" from its lowest-numbered corner v: one tet from
/// v to each triangle of the faces that do not contain v, a quadrangle face being cut along
/// the diagonal through its own lowest-numbered corner. The cut of a face depends only on the
/// face's global node numbers, so neighboring cells cut a shared face alike (conforming), and
/// the faces that contain v are cut through v, which is their lowest corner too. Hexahedron:
/// v lies on 3 faces, the other 3 give 6 tets; prism: 1 triangle + 1 quadrangle, 3 tets;
/// pyramid: 2 tets whichever corner v is. A face listed counter-clockwise from outside and v
/// inside give a positive signed volume for (v, a, b, c).
void splitCell(const CellShape& shape, const std::int32_t* corner, std::vector<Tet>& tets)
{
  int v = 0;
  for (int i = 1; i < shape.nodes; ++i)
  {
    if (corner[i] < corner[v])
      v = i;
  }
  for (const std::vector<int>& f : shape.faces)
  {
    if (std::find(f.begin(), f.end(), v) != f.end())
    {
      continue;
    }
    if (f.size() == 3)
    {
      tets.push_back({ corner[v], corner[f[0]], corner[f[1]], corner[f[2]] });
      continue;
    }
    int low = 0;
    for (int i = 1; i < 4; ++i)
    {
      if (corner[f[i]] < corner[f[low]])
        low = i;
    }
    // Diagonal a-c when the lowest corner is a or c, else b-d; both keep the face's orientation.
    const int a = f[low % 2], b = f[low % 2 + 1], c = f[low % 2 + 2], d = f[(low % 2 + 3) % 4];
    tets.push_back({ corner[v], corner[a], corner[b], corner[c] });
    tets.push_back({ corner[v], corner[a], corner[c], corner[d] });
  }
}

/// The dimension of a Gmsh element type (points 0, lines 1, surfaces 2, volumes 3, linear and
/// higher order); -1 for a type this reader does not know.
int elementDimension(long long type)
{
  switch (type)
  {
    case 15:
      return 0;
    case 1: case 8: case 26: case 27: case 28:
      return 1;
    case 2: case 3: case 9: case 10: case 16: case 20: case 21: case 22: case 23: case 24: case 25:
      return 2;
    case 4: case 5: case 6: case 7: case 11: case 12: case 13: case 14: case 17: case 18: case 19:
    case 29: case 30: case 31: case 92: case 93:
      return 3;
    default:
      return -1;
  }
}

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
  std::map<long long, std::size_t> Split;       ///< Gmsh type -> cells split into tets
  std::map<long long, std::size_t> HigherOrder; ///< Gmsh type -> refused cells
  // Physical groups and elementary entities. The element being read: its entity and physical
  // tags (format 4.1: those of its block's entity, from $Entities).
  long long EntityTag = 0;
  std::vector<long long> PhysicalTags;
  int Dimension = 0;
  std::map<std::pair<int, long long>, std::vector<long long>> EntityPhysicals; ///< 4.1 $Entities
  std::map<std::pair<int, long long>, std::string> PhysicalNames;
  std::map<std::pair<int, long long>, std::vector<std::int32_t>> GroupNodes; ///< (dim, tag)
  std::vector<long long> TetPhysical, TetEntity;

  /// The nodes of the element line from token `first` on belong to its physical groups.
  void recordGroups(std::size_t first)
  {
    for (long long physical : this->PhysicalTags)
    {
      std::vector<std::int32_t>& nodes = this->GroupNodes[{ this->Dimension, physical }];
      for (std::size_t t = first; t < this->Tokens.size(); ++t)
      {
        nodes.push_back(this->node(t));
      }
    }
  }
  /// The tets the element added carry its tags.
  void tagTets()
  {
    const long long physical = this->PhysicalTags.empty() ? 0 : this->PhysicalTags.front();
    this->TetPhysical.resize(this->Mesh.tets.size(), physical);
    this->TetEntity.resize(this->Mesh.tets.size(), this->EntityTag);
  }

  /// A cell of `type` whose first node is token `firstNodeToken`: a tet is stored, a hexahedron,
  /// prism or pyramid split, a higher-order volume cell counted for the refusal, anything
  /// else (points, lines, surfaces) skipped. The line must hold exactly the cell's nodes.
  void addCell(long long type, std::size_t firstNodeToken)
  {
    this->addShape(type, firstNodeToken);
    this->tagTets();
    if (this->Dimension >= 0)
    {
      this->recordGroups(firstNodeToken);
    }
  }

  void addShape(long long type, std::size_t firstNodeToken)
  {
    if (type == 4)
    {
      this->checkNodeCount(type, 4, firstNodeToken);
      this->addTet(firstNodeToken);
      return;
    }
    if (const CellShape* shape = splitShapeOf(type))
    {
      this->checkNodeCount(type, shape->nodes, firstNodeToken);
      std::array<std::int32_t, 8> corner{};
      for (int c = 0; c < shape->nodes; ++c)
      {
        corner[static_cast<std::size_t>(c)] = this->node(firstNodeToken + static_cast<std::size_t>(c));
      }
      splitCell(*shape, corner.data(), this->Mesh.tets);
      ++this->Split[type];
      return;
    }
    if (higherOrderVolumeName(type))
    {
      ++this->HigherOrder[type];
      return;
    }
    ++this->Skipped;
  }

  void checkNodeCount(long long type, int nodes, std::size_t firstNodeToken) const
  {
    if (this->Tokens.size() != firstNodeToken + static_cast<std::size_t>(nodes))
    {
      this->fail("an element of type " + std::to_string(type) + " needs " + std::to_string(nodes) +
        " nodes after its " + std::to_string(firstNodeToken) + " leading numbers, the line has " +
        std::to_string(this->Tokens.size()) + " numbers: '" + printableExcerpt(this->Line) + "'.");
    }
  }

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
        printableExcerpt(this->Line) + "'.");
    }
  }

  long long integer(std::size_t i, const char* what) const
  {
    const std::string_view t = this->Tokens[i];
    long long v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
    {
      this->fail(std::string("expected an integer ") + what + ", found '" + printableExcerpt(t) + "'.");
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
      this->fail("expected a finite coordinate, found '" + printableExcerpt(t) + "'.");
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

  /// The index of the node whose tag is token i.
  std::int32_t node(std::size_t i) const
  {
    const long long tag = this->integer(i, "node tag");
    const auto it = this->NodeIndex.find(tag);
    if (it == this->NodeIndex.end())
    {
      this->fail("an element names node " + std::to_string(tag) + ", which is not in $Nodes.");
    }
    return it->second;
  }

  void addTet(std::size_t firstNodeToken)
  {
    Tet tet;
    for (int c = 0; c < 4; ++c)
    {
      tet[c] = this->node(firstNodeToken + static_cast<std::size_t>(c));
    }
    this->Mesh.tets.push_back(tet);
  }

  void expectEnd(const char* endTag)
  {
    this->require(endTag);
    if (this->Line.rfind(endTag, 0) != 0)
    {
      this->fail(std::string("expected ") + endTag + ", found '" + printableExcerpt(this->Line) +
        "' (a count in the section header does not match its content?).");
    }
  }

  void readFormat();
  void readNodes2();
  void readElements2();
  void readNodes4();
  void readElements4();
  void readEntities4();
  void readPhysicalNames();
  void skipSection(const std::string& name);

public:
  /// The physical groups that have elements, and the tets' tags, into `info`.
  void reportGroups(MeshFileInfo& info) const;
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
    this->fail("unsupported .msh format version '" + printableExcerpt(version) +
      "'; ASCII 2.2 and 4.1 are read.");
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
    this->integer(0, "element tag");
    if (this->Tokens.size() < 3 + tags)
    {
      this->fail("an element line announces " + std::to_string(tags) + " tags but has fewer numbers: '" +
        printableExcerpt(this->Line) + "'.");
    }
    // Tags: the physical group (0: none), then the elementary entity.
    const long long physical = tags >= 1 ? this->integer(3, "physical tag") : 0;
    this->PhysicalTags.assign(physical != 0 ? 1 : 0, physical);
    this->EntityTag = tags >= 2 ? this->integer(4, "elementary tag") : 0;
    this->Dimension = elementDimension(type);
    this->addCell(type, 3 + tags);
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
      this->fail("invalid node block header '" + printableExcerpt(this->Line) + "'.");
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
    this->Dimension = static_cast<int>(this->integer(0, "entity dimension"));
    this->EntityTag = this->integer(1, "entity tag");
    const auto physicals = this->EntityPhysicals.find({ this->Dimension, this->EntityTag });
    this->PhysicalTags = physicals != this->EntityPhysicals.end() ? physicals->second : std::vector<long long>{};
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
      this->requireTokens("an element line (tag node...)", 2, true);
      this->integer(0, "element tag");
      this->addCell(type, 1);
    }
  }
  if (seen != total)
  {
    this->fail("the $Elements header announces " + std::to_string(total) +
      " elements, the blocks hold " + std::to_string(seen) + ".");
  }
  this->expectEnd("$EndElements");
}

void MshParser::readPhysicalNames()
{
  // numPhysicalNames, then: dimension physicalTag "name" (the name may hold blanks).
  this->requireTokens("$PhysicalNames header", 1);
  const std::size_t n = this->count(0, "physical name count");
  for (std::size_t i = 0; i < n; ++i)
  {
    this->requireTokens("a physical name line (dimension tag \"name\")", 3, true);
    const int dimension = static_cast<int>(this->integer(0, "dimension"));
    const long long tag = this->integer(1, "physical tag");
    const std::size_t open = this->Line.find('"'), close = this->Line.rfind('"');
    if (open == std::string::npos || close <= open)
    {
      this->fail("a physical name must be quoted: '" + printableExcerpt(this->Line) + "'.");
    }
    this->PhysicalNames[{ dimension, tag }] = this->Line.substr(open + 1, close - open - 1);
  }
  this->expectEnd("$EndPhysicalNames");
}

void MshParser::readEntities4()
{
  // numPoints numCurves numSurfaces numVolumes; a point: tag x y z numPhysicalTags tags...;
  // a curve, surface or volume: tag minX minY minZ maxX maxY maxZ numPhysicalTags tags... then
  // its bounding entities (not needed here).
  this->requireTokens("$Entities header", 4);
  std::array<std::size_t, 4> counts{};
  for (std::size_t d = 0; d < 4; ++d)
  {
    counts[d] = this->count(d, "entity count");
  }
  for (int dimension = 0; dimension < 4; ++dimension)
  {
    const std::size_t physicalAt = dimension == 0 ? 4 : 7;
    for (std::size_t i = 0; i < counts[static_cast<std::size_t>(dimension)]; ++i)
    {
      this->requireTokens("an entity line", physicalAt + 1, true);
      const long long tag = this->integer(0, "entity tag");
      const std::size_t n = this->count(physicalAt, "number of physical tags");
      if (this->Tokens.size() < physicalAt + 1 + n)
      {
        this->fail("an entity line announces " + std::to_string(n) + " physical tags but has fewer numbers.");
      }
      std::vector<long long>& physicals = this->EntityPhysicals[{ dimension, tag }];
      for (std::size_t k = 0; k < n; ++k)
      {
        // Gmsh writes a negative tag for a group whose orientation is reversed: same group.
        physicals.push_back(std::abs(this->integer(physicalAt + 1 + k, "physical tag")));
      }
    }
  }
  this->expectEnd("$EndEntities");
}

void MshParser::reportGroups(MeshFileInfo& info) const
{
  info.tetPhysicalTag = this->TetPhysical;
  info.tetEntityTag = this->TetEntity;
  info.groups.clear();
  for (const auto& [key, nodes] : this->GroupNodes)
  {
    MeshGroup group;
    group.dimension = key.first;
    group.tag = key.second;
    const auto named = this->PhysicalNames.find(key);
    group.name = named != this->PhysicalNames.end() && !named->second.empty()
      ? named->second
      : "Physical " + std::to_string(key.first) + "D " + std::to_string(key.second);
    group.points.assign(this->Mesh.points.size(), 0);
    for (std::int32_t p : nodes)
    {
      group.points[static_cast<std::size_t>(p)] = 1;
    }
    info.groups.push_back(std::move(group));
  }
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
  this->fail("section " + printableExcerpt(name) + " has no " + printableExcerpt(endTag) +
    " (truncated file?).");
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
      this->fail("expected a section such as $Nodes, found '" + printableExcerpt(this->Line) +
        "' (not a Gmsh .msh file, or garbled).");
    }
    if (!seenFormat && section != "$MeshFormat")
    {
      this->fail("a .msh file starts with $MeshFormat, found '" + printableExcerpt(section) + "'.");
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
    else if (section == "$PhysicalNames")
    {
      this->readPhysicalNames();
    }
    else if (section == "$Entities" && this->Version4)
    {
      this->readEntities4();
    }
    else if (section.rfind("$End", 0) == 0)
    {
      this->fail("unexpected " + printableExcerpt(section) + " outside its section.");
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
  if (!this->HigherOrder.empty())
  {
    std::size_t total = 0;
    std::string list;
    for (const auto& [type, n] : this->HigherOrder)
    {
      total += n;
      list += (list.empty() ? "" : ", ") + std::to_string(n) + " " + higherOrderVolumeName(type) +
        " (type " + std::to_string(type) + ")";
    }
    this->fail("the mesh holds " + std::to_string(total) + " volume elements of second or higher "
      "order (" + list + "), which are not read: only linear tetrahedra, hexahedra, prisms and "
      "pyramids are. Save the mesh with element order 1 (Gmsh: Mesh > Set order 1).");
  }
  if (this->Mesh.tets.empty())
  {
    this->fail("the mesh holds no tetrahedra, hexahedra, prisms or pyramids (" +
      std::to_string(this->Skipped) + " other elements skipped). Generate a 3-D mesh in Gmsh "
      "(Mesh > 3D).");
  }
  if (info)
  {
    this->reportGroups(*info);
    info->format = this->Version4 ? "Gmsh 4.1" : "Gmsh 2.2";
    info->skippedElements = this->Skipped;
    info->convertedElements = 0;
    for (const auto& [type, n] : this->Split)
    {
      const CellShape& shape = *splitShapeOf(type);
      info->convertedElements += n;
      info->warnings.push_back(this->Name + ": split " + std::to_string(n) + " " + (n == 1 ? shape.one : shape.name) +
        " (Gmsh element type " + std::to_string(type) + ") into " +
        std::to_string(n * static_cast<std::size_t>(shape.tetsPerCell)) +
        " tetrahedra (conforming: shared faces are cut alike); the body is simulated as "
        "tetrahedra.");
    }
  }
  return std::move(this->Mesh);
}

} // namespace

std::string printableExcerpt(std::string_view text, std::size_t maxChars)
{
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i)
  {
    const auto byte = static_cast<unsigned char>(text[i]);
    char piece[8] = { static_cast<char>(byte), '\0' };
    if (byte == '\t')
    {
      std::snprintf(piece, sizeof piece, "\\t");
    }
    else if (byte < 0x20 || byte >= 0x7f)
    {
      std::snprintf(piece, sizeof piece, "\\x%02X", static_cast<unsigned>(byte));
    }
    // The limit counts what is shown, escapes included; "..." says that more followed.
    if (out.size() + std::char_traits<char>::length(piece) > maxChars)
    {
      out += "...";
      break;
    }
    out += piece;
  }
  return out;
}

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
