// A contact's constraint as one relative coordinate r = sum_j c_j x_j of its participants (the
// point and what it touches), C = n . (r - s) - thickness: the form every response uses, so
// that a correction split as c_j w_j / W keeps momentum (W = sum_j c_j^2 w_j).
#pragma once

#include "softbody/collision/contact.h"

#include <array>
#include <cstdint>

namespace softbody
{

struct ContactTerms
{
  int count = 0;
  std::array<std::int32_t, 4> index{};
  std::array<double, 4> coefficient{};
};

/// Obstacle: c = {1} (the surface is not simulated); PointPoint: {1, -1}; PointTriangle:
/// {1, -b0, -b1, -b2}; EdgeEdge: {1 - s, s, -(1 - t), -t} (contact.h).
inline ContactTerms termsOf(const Contact& contact)
{
  ContactTerms terms;
  terms.index[0] = contact.point;
  terms.coefficient[0] = 1.0;
  switch (contact.kind)
  {
    case ContactKind::Obstacle:
      terms.count = 1;
      break;
    case ContactKind::PointPoint:
      terms.count = 2;
      terms.index[1] = contact.other[0];
      terms.coefficient[1] = -1.0;
      break;
    case ContactKind::PointTriangle:
      terms.count = 4;
      for (int k = 0; k < 3; ++k)
      {
        terms.index[k + 1] = contact.other[k];
        terms.coefficient[k + 1] = -contact.barycentric[k];
      }
      break;
    case ContactKind::EdgeEdge:
    {
      const double s = contact.barycentric[0], t = contact.barycentric[1];
      terms.count = 4;
      terms.index = { contact.point, contact.other[0], contact.other[1], contact.other[2] };
      terms.coefficient = { 1.0 - s, s, -(1.0 - t), -t };
      break;
    }
  }
  return terms;
}

} // namespace softbody
