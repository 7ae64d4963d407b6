#include "model/cell_geometry.h"

#include <fmt/format.h>

#include <sstream>
#include <stdexcept>

namespace cmcsurf {

std::vector<double> parse_parallel_distances(const std::string& text) {
  std::vector<double> out;
  if (text.empty()) return out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double l = 0.0;
    try {
      l = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !(l > 0.0 && l < kMaxParallelDistance))
      throw std::invalid_argument(fmt::format(
          "got '{}' in '{}'; accepted: a comma-separated list of distances 0 < l < {} (cell "
          "units), or '' for none",
          item, text, kMaxParallelDistance));
    out.push_back(l);
  }
  if (text.back() == ',')
    throw std::invalid_argument(fmt::format("got '{}' (a trailing comma); accepted: a "
                                            "comma-separated list of distances",
                                            text));
  if (int(out.size()) > kMaxParallelDistances)
    throw std::invalid_argument(fmt::format("got {} distances; accepted: at most {}", out.size(),
                                            kMaxParallelDistances));
  return out;
}

}  // namespace cmcsurf
