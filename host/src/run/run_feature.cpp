// What every run feature does unless it says otherwise (run_feature.hpp).
#include "run/run_feature.hpp"

#include <noether/error.hpp>

#include "io/frame_schema.hpp"

#include <algorithm>

namespace noether::detail {

// A recorded frame's series, as the file holds them: a continued run copies them as they were.
void RunFeature::recorded(const io::RecordedFrame& frame, std::span<const double>, std::span<double> out) const {
  std::size_t at = 0;
  for (const FeatureSeries& s : series()) {
    const std::span<const double> values = frame.series_named(s.name);
    if (values.size() != s.size())
      throw Error("the recorded frame at t = " + std::to_string(frame.state.t) + " holds " +
                  std::to_string(values.size()) + " numbers of the series '" + s.name + "', not the " +
                  std::to_string(s.size()) + " the run writes (" + std::string(name()) +
                  "): its file was written for another scene; run it again whole");
    std::copy(values.begin(), values.end(), out.begin() + static_cast<std::ptrdiff_t>(at));
    at += s.size();
  }
}

}  // namespace noether::detail
