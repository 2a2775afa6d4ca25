// What every benchmark program shares: its command line and a hash of a final state (equal
// hashes at every thread count show the runs computed the same thing).
#pragma once

#include "softbody/common/geometry.h"

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace softbody::bench
{

struct Options
{
  bool smoke = false;                  ///< --smoke: a few seconds, for CTest
  std::string dataDir = "../shared/data"; ///< --data: the public meshes, when present
  std::string csv;                     ///< --csv: output file (or prefix)
};

/// Parses --smoke, --data DIR, --csv PATH; prints the usage and exits on anything else.
inline Options parseOptions(int argc, char** argv, const std::string& program, const std::string& defaultCsv)
{
  Options options;
  options.csv = defaultCsv;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--smoke")
    {
      options.smoke = true;
    }
    else if (arg == "--data" && i + 1 < argc)
    {
      options.dataDir = argv[++i];
    }
    else if (arg == "--csv" && i + 1 < argc)
    {
      options.csv = argv[++i];
    }
    else
    {
      std::cerr << "usage: " << program << " [--smoke] [--data DIR] [--csv PATH]\n";
      std::exit(2);
    }
  }
  return options;
}

/// FNV-1a over the bytes of the positions.
inline std::uint64_t hashPositions(const std::vector<Vec3>& x)
{
  std::uint64_t hash = 1469598103934665603ull;
  const auto* bytes = reinterpret_cast<const unsigned char*>(x.data());
  for (std::size_t i = 0; i < x.size() * sizeof(Vec3); ++i)
  {
    hash = (hash ^ bytes[i]) * 1099511628211ull;
  }
  return hash;
}

} // namespace softbody::bench
