// The output's series as users see them (noether/output_schema.hpp: `noether.output_series()`,
// docs/user-guide.md "Output"): the frame schema's rows in words and units.
#include "io/frame_schema.hpp"

#include <noether/output_schema.hpp>

namespace noether {

std::vector<OutputSeries> output_series(const Units& units) {
  std::vector<OutputSeries> out;
  for (const auto& q : io::frame_schema()) {
    OutputSeries s;
    s.name = q.name;
    s.path = q.path;
    s.shape = io::describe_extent(q.extent);
    s.unit = io::unit_of(q.unit, units);
    s.description = q.description;
    s.integer = io::is_integer(q);
    s.rigid_only = io::rigid_only(q);
    s.optional = io::optional(q);
    s.needs = io::requirement(q);
    s.checkpointed = q.checksum_column >= 0;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace noether
