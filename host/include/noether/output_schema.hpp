#pragma once
// The series of an output file as data: one entry per series that holds a value per frame, from
// the same table the writer and the readers use (host/src/io/frame_schema.hpp). The Python
// reader's names come from here (noether.output_series()).
#include <noether/units.hpp>

#include <string>
#include <vector>

namespace noether {

struct OutputSeries {
  std::string name;         // the Python reader's name: noether.read(file)["positions"]
  std::string path;         // the dataset: "/particles/bodies/position/value"
  std::string shape;        // "[frame][body][3]"
  std::string unit;         // in the given units: "km", "kg km^2/h"
  std::string description;
  bool integer = false;       // int64 values, else double
  bool rigid_only = false;    // written when the scene has rigid bodies
  bool optional = false;      // written only when `needs` holds (an integrator with variables of its own, run.stm)
  bool checkpointed = false;  // read back and verified by a continuation
  // What a scene needs for the series to be written: "" (always), "rigid bodies", "an integrator
  // with variables of its own", "a binary" (two bodies hold 99 % of the mass), "a binary with a
  // rigid primary", "a binary with a rigid secondary".
  std::string needs;
};

std::vector<OutputSeries> output_series(const Units& units = {});

}  // namespace noether
