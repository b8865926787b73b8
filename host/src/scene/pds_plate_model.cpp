// A plate shape model as the PDS archives it (noether/pds_plate_model.hpp).
#include <noether/error.hpp>
#include <noether/pds3_label.hpp>
#include <noether/pds_plate_model.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace noether {

namespace {

// A table object of the label, where its rows lie in the file and how its three-item column is
// laid out (START_BYTE, ITEM_BYTES), with its flag column's letter position when it has one.
struct Layout {
  std::filesystem::path file;
  std::size_t first = 0, first_record = 0;  // byte offset of its first row in the file, its record (0-based)
  std::size_t rows = 0, row_bytes = 0;
  std::size_t start = 0, item_bytes = 0;  // the three items, 0-based start
  std::string unit;            // the column's UNIT ("" when none)
  std::size_t flag = std::string::npos;  // the flag column's byte, 0-based
};

Layout layout(const Pds3Object& label, const std::string& object, const std::filesystem::path& label_file) {
  const std::string name = label_file.string();
  const Pds3Object* table = label.object(object);
  if (!table) throw SceneError(name + ": the label has no " + object + " object (is it a plate model?)");
  Layout out;
  const Pds3Pointer pointer = pds3_pointer(label, "^" + object, label_file);
  out.file = pointer.file;
  out.rows = pds3_count(*table, "ROWS", name);
  out.row_bytes =
      table->find("ROW_BYTES") ? pds3_count(*table, "ROW_BYTES", name) : pds3_count(label, "RECORD_BYTES", name);
  const std::size_t record = label.find("RECORD_BYTES") ? pds3_count(label, "RECORD_BYTES", name) : out.row_bytes;
  out.first_record = pointer.record - 1;
  out.first = out.first_record * record;
  bool found = false;
  for (const Pds3Object& c : table->objects) {
    if (c.name != "COLUMN") continue;
    const std::size_t start = pds3_count(c, "START_BYTE", name) - 1;
    if (const Pds3Value* items = c.find("ITEMS"); items && items->text == "3") {
      out.start = start;
      out.item_bytes = c.find("ITEM_BYTES") ? pds3_count(c, "ITEM_BYTES", name) : pds3_count(c, "BYTES", name) / 3;
      if (const Pds3Value* unit = c.find("UNIT")) out.unit = pds3_upper(unit->text);
      found = true;
    } else if (c.find("BYTES") && c.find("BYTES")->text == "1") {
      out.flag = start;
    }
  }
  if (!found)
    throw SceneError(name + ":" + std::to_string(table->line) + ": " + object +
                     " has no column of three ITEMS (the coordinates, or the vertex offsets)");
  if (out.start + 3 * out.item_bytes > out.row_bytes)
    throw SceneError(name + ":" + std::to_string(table->line) + ": " + object + "'s items end past its " +
                     std::to_string(out.row_bytes) + "-byte rows");
  return out;
}

}  // namespace

PdsPlateModel read_pds_plate_model(const std::filesystem::path& label_file, double scale_per_metre) {
  const Pds3Object label = read_pds3_label(label_file);
  const Layout v = layout(label, "VERTEX_TABLE", label_file), f = layout(label, "FACET_TABLE", label_file);
  PdsPlateModel out;
  if (v.unit == "KILOMETER" || v.unit == "KILOMETERS" || v.unit == "KM")
    out.unit_in_metres = 1e3;
  else if (v.unit == "METER" || v.unit == "METERS" || v.unit == "M")
    out.unit_in_metres = 1.0;
  else
    throw SceneError(label_file.string() + ": the vertices' UNIT is '" + v.unit +
                     "', which noether does not read (KILOMETER or METER)");
  if (v.rows > kMaxMeshVertices || f.rows > kMaxMeshFaces)
    throw SceneError(label_file.string() + ": " + std::to_string(v.rows) + " vertices and " + std::to_string(f.rows) +
                     " plates; noether reads at most " + std::to_string(kMaxMeshFaces) + " faces");
  if (const Pds3Value* id = label.find("PRODUCT_ID")) out.model = id->text;
  else out.model = label_file.filename().string();
  const std::string vertices_text = read_pds3_file(v.file, kMaxShapeFileBytes);
  const std::string facets_text = f.file == v.file ? std::string() : read_pds3_file(f.file, kMaxShapeFileBytes);
  const std::string& facets_data = f.file == v.file ? vertices_text : facets_text;
  auto row_of = [](const Layout& t, const std::string& data, std::size_t r) {
    const std::size_t at = t.first + r * t.row_bytes;
    if (at + t.row_bytes > data.size())
      throw SceneError(t.file.string() + ": " + std::to_string(data.size()) + " bytes end before row " +
                       std::to_string(r + 1) + " of the " + std::to_string(t.rows) +
                       " its label declares: the file is cut short; fetch it whole again");
    return std::string_view(data).substr(at, t.row_bytes);
  };
  auto item = [](std::string_view row, const Layout& t, int k) {
    std::string cell(row.substr(t.start + static_cast<std::size_t>(k) * t.item_bytes, t.item_bytes));
    const auto b = cell.find_first_not_of(' ');
    return b == std::string::npos ? std::string() : cell.substr(b, cell.find_last_not_of(' ') - b + 1);
  };
  // The record's line in the file (for messages): its row number counted from the file's start.
  auto line_of = [](const Layout& t, std::size_t r) { return t.first_record + r + 1; };
  Mesh& mesh = out.mesh;
  mesh.source = v.file.string();
  mesh.vertices.resize(3, static_cast<Eigen::Index>(v.rows));
  const double scale = out.unit_in_metres * scale_per_metre;
  for (std::size_t r = 0; r < v.rows; ++r) {
    const std::string_view row = row_of(v, vertices_text, r);
    const std::string where = v.file.string() + ":" + std::to_string(line_of(v, r)) + ": ";
    if (v.flag != std::string::npos && row[v.flag] != 'v' && row[v.flag] != 'V')
      throw SceneError(where + "a vertex row of the label's VERTEX_TABLE does not start with 'v'");
    for (int k = 0; k < 3; ++k) {
      const std::string cell = item(row, v, k);
      errno = 0;
      char* end = nullptr;
      const double x = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x))
        throw SceneError(where + "coordinate '" + cell + "' is not a finite number");
      mesh.vertices(k, static_cast<Eigen::Index>(r)) = x * scale;
    }
  }
  mesh.faces.reserve(f.rows);
  mesh.face_lines.reserve(f.rows);
  for (std::size_t r = 0; r < f.rows; ++r) {
    const std::string_view row = row_of(f, facets_data, r);
    const std::string where = f.file.string() + ":" + std::to_string(line_of(f, r)) + ": ";
    if (f.flag != std::string::npos && row[f.flag] != 'f' && row[f.flag] != 'F')
      throw SceneError(where + "a plate row of the label's FACET_TABLE does not start with 'f'");
    std::array<int, 3> face{};
    for (int k = 0; k < 3; ++k) {
      const std::string cell = item(row, f, k);
      char* end = nullptr;
      const long i = std::strtol(cell.c_str(), &end, 10);
      if (cell.empty() || *end != '\0' || i < 0 || static_cast<std::size_t>(i) >= v.rows)
        throw SceneError(where + "vertex offset '" + cell + "' is not one of 0.." + std::to_string(v.rows - 1) +
                         " (a plate model's offsets count from 0, the first vertex row)");
      face[static_cast<std::size_t>(k)] = static_cast<int>(i);
    }
    mesh.faces.push_back(face);
    mesh.face_lines.push_back(static_cast<int>(line_of(f, r)));
  }
  return out;
}

}  // namespace noether
