#pragma once
// A plate (polyhedron) shape model as the Planetary Data System archives it: a PDS3 label and the
// fixed-length table its ^VERTEX_TABLE and ^FACET_TABLE point into — `v x y z` rows in the
// label's UNIT, then `f i j k` rows of 0-based vertex offsets (NEAR MSI's Eros models; not OBJ's
// 1-based indices) — in the archive's body-fixed frame (docs/gravity-fields.md "Archived
// shapes"). Errors name the file and row.
#include <noether/mesh.hpp>

#include <filesystem>
#include <string>

namespace noether {

struct PdsPlateModel {
  Mesh mesh;                    // vertices in the unit asked for (read_pds_plate_model)
  double unit_in_metres = 1.0;  // the label's unit for the coordinates (KILOMETER: 1000)
  std::string model;            // the label's PRODUCT_ID (or the file's name)
};

// The plate model of `label`, its coordinates multiplied by `scale_per_metre` after conversion
// to metres (1 for metres; 1/1000 for a scene in km). Throws SceneError.
PdsPlateModel read_pds_plate_model(const std::filesystem::path& label, double scale_per_metre);

}  // namespace noether
