#include "softbody/mesh/topology.h"

#include <algorithm>
#include <cstdint>

namespace softbody
{
namespace
{

// The six edges of a tet as corner pairs.
constexpr int kTetEdgeCorners[6][2] = { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 2 }, { 1, 3 }, { 2, 3 } };

Edge makeEdge(std::int32_t p, std::int32_t q)
{
  return p < q ? Edge{ p, q } : Edge{ q, p };
}

bool edgeLess(const Edge& l, const Edge& r)
{
  return l.a < r.a || (l.a == r.a && l.b < r.b);
}

std::int32_t findEdge(const Topology& topology, Edge edge)
{
  const Csr& incidence = topology.vertexEdges;
  for (std::int32_t k = incidence.offsets[edge.a]; k < incidence.offsets[edge.a + 1]; ++k)
  {
    const std::int32_t e = incidence.items[k];
    if (topology.edges[e].b == edge.b)
    {
      return e;
    }
  }
  return -1; // unreachable for edges that came from the same tets
}

} // namespace

std::vector<Edge> extractUniqueEdges(const std::vector<Tet>& tets)
{
  std::vector<Edge> edges;
  edges.reserve(tets.size() * 6);
  for (const Tet& tet : tets)
  {
    for (const auto& corners : kTetEdgeCorners)
    {
      edges.push_back(makeEdge(tet[corners[0]], tet[corners[1]]));
    }
  }
  std::sort(edges.begin(), edges.end(), edgeLess);
  edges.erase(std::unique(edges.begin(), edges.end(),
                [](const Edge& l, const Edge& r) { return l.a == r.a && l.b == r.b; }),
    edges.end());
  return edges;
}

Csr buildCsr(std::size_t rowCount, const std::vector<std::int32_t>& rows,
  const std::vector<std::int32_t>& items)
{
  Csr csr;
  csr.offsets.assign(rowCount + 1, 0);
  for (std::int32_t row : rows)
  {
    ++csr.offsets[row + 1];
  }
  for (std::size_t i = 0; i < rowCount; ++i)
  {
    csr.offsets[i + 1] += csr.offsets[i];
  }
  csr.items.resize(items.size());
  std::vector<std::int32_t> cursor(csr.offsets.begin(), csr.offsets.end() - 1);
  for (std::size_t k = 0; k < items.size(); ++k)
  {
    csr.items[cursor[rows[k]]++] = items[k];
  }
  return csr;
}

Topology buildTopology(std::size_t vertexCount, std::vector<Tet> tets)
{
  Topology topology;
  topology.vertexCount = vertexCount;
  topology.tets = std::move(tets);
  topology.edges = extractUniqueEdges(topology.tets);

  std::vector<std::int32_t> rows, items;
  rows.reserve(topology.edges.size() * 2);
  items.reserve(topology.edges.size() * 2);
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
  {
    rows.push_back(topology.edges[e].a);
    items.push_back(static_cast<std::int32_t>(e));
    rows.push_back(topology.edges[e].b);
    items.push_back(static_cast<std::int32_t>(e));
  }
  topology.vertexEdges = buildCsr(vertexCount, rows, items);

  rows.clear();
  items.clear();
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    for (std::int32_t corner = 0; corner < 4; ++corner)
    {
      rows.push_back(topology.tets[t][corner]);
      items.push_back(static_cast<std::int32_t>(4 * t) + corner);
    }
  }
  topology.vertexTetCorners = buildCsr(vertexCount, rows, items);

  topology.tetEdges.offsets.resize(topology.tets.size() + 1);
  topology.tetEdges.items.resize(topology.tets.size() * 6);
  for (std::size_t t = 0; t < topology.tets.size(); ++t)
  {
    topology.tetEdges.offsets[t] = static_cast<std::int32_t>(6 * t);
    for (int k = 0; k < 6; ++k)
    {
      const Tet& tet = topology.tets[t];
      topology.tetEdges.items[6 * t + k] =
        findEdge(topology, makeEdge(tet[kTetEdgeCorners[k][0]], tet[kTetEdgeCorners[k][1]]));
    }
  }
  topology.tetEdges.offsets.back() = static_cast<std::int32_t>(topology.tetEdges.items.size());
  return topology;
}

} // namespace softbody
