// A gravity field as the Planetary Data System archives it: a PDS3 label and the fixed-length
// ASCII table it describes (stokes_file.hpp, format `pds`; docs/gravity-fields.md "Archived
// fields"). The table's columns are found by the label's NAME, START_BYTE and BYTES; the degree,
// normalization, reference radius and GM — which such tables do not hold — from the label's
// DESCRIPTION text, where NEAR's Eros fields state them ("Reference Radius:  16.0km",
// "Gravitational Constant, GM:   4.46275472004E-04 km^3/s^2"). Defects of real files are read as
// they are and named (StokesFile::defects).
#include <noether/error.hpp>
#include <noether/pds3_label.hpp>
#include <noether/stokes_file.hpp>

#include "scene/stokes_rows.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>

namespace noether {

namespace {

using namespace detail;

// The text after `phrase` (any case) in `text`, or nothing.
std::optional<std::string> after(const std::string& text, const std::string& phrase) {
  const std::string t = pds3_upper(text), p = pds3_upper(phrase);
  const auto at = t.find(p);
  if (at == std::string::npos) return std::nullopt;
  return text.substr(at + phrase.size());
}

// A number and the unit written after it, glued ("16.0km") or not ("4.46E-04 km^3/s^2").
struct Quantity {
  double value;
  std::string unit;
};
std::optional<Quantity> quantity(const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || !std::isfinite(v)) return std::nullopt;
  std::string rest(end);
  const auto b = rest.find_first_not_of(" \t");
  if (b == std::string::npos) return Quantity{v, ""};
  const auto e = rest.find_first_of(" \t\r\n", b);
  return Quantity{v, rest.substr(b, e == std::string::npos ? std::string::npos : e - b)};
}

// The label's statement of `what` (a phrase of its DESCRIPTION) in SI: lengths km or m, GM
// km^3/s^2 or m^3/s^2.
std::optional<double> stated(const std::string& description, std::initializer_list<const char*> phrases,
                             bool gm, const std::string& file, std::size_t line) {
  for (const char* phrase : phrases) {
    const auto text = after(description, phrase);
    if (!text) continue;
    const auto q = quantity(*text);
    if (!q) throw SceneError(file + ":" + std::to_string(line) + ": its DESCRIPTION's '" + phrase + "' has no number");
    const std::string unit = q->unit;
    if (!gm && (unit == "km" || unit == "KM")) return q->value * 1e3;
    if (!gm && (unit == "m" || unit == "M")) return q->value;
    if (gm && (unit == "km^3/s^2" || unit == "KM^3/S^2" || unit == "km**3/s**2")) return q->value * 1e9;
    if (gm && (unit == "m^3/s^2" || unit == "M^3/S^2" || unit == "m**3/s**2")) return q->value;
    throw SceneError(file + ":" + std::to_string(line) + ": its DESCRIPTION's '" + phrase + "' is in '" + unit +
                     "', which noether does not read (" + (gm ? "km^3/s^2 or m^3/s^2" : "km or m") + ")");
  }
  return std::nullopt;
}

// One column the table's label describes: where it lies in a row (0-based) and how long it is.
struct Column {
  std::string name;
  std::size_t start = 0, bytes = 0;
};

enum class Role { kDegree, kOrder, kC, kS, kSigmaC, kSigmaS, kOther };
Role role_of(const std::string& name) {
  const std::string n = pds3_upper(name);
  if (n == "DEGREE" || n == "N" || n == "L") return Role::kDegree;
  if (n == "ORDER" || n == "M") return Role::kOrder;
  const bool sigma = n.find("UNC") != std::string::npos || n.find("SIG") != std::string::npos ||
                     n.find("ERR") != std::string::npos;
  if (!n.empty() && n[0] == 'C') return sigma ? Role::kSigmaC : Role::kC;
  if (!n.empty() && n[0] == 'S') return sigma ? Role::kSigmaS : Role::kS;
  return Role::kOther;
}

}  // namespace

StokesFile read_pds_stokes(const std::filesystem::path& file) {
  const std::string name = file.string();
  const Pds3Object label = read_pds3_label(file);
  const Pds3Object* table = label.object("TABLE");
  if (!table) throw SceneError(name + ": the label describes no TABLE object");
  auto whole = [&](const Pds3Object& o, const char* key) { return pds3_count(o, key, name); };
  const std::size_t rows = whole(*table, "ROWS");
  const std::size_t row_bytes =
      table->find("ROW_BYTES") ? whole(*table, "ROW_BYTES") : whole(label, "RECORD_BYTES");
  // The columns, by role.
  std::optional<Column> columns[6];
  for (const Pds3Object& o : table->objects) {
    if (o.name != "COLUMN") continue;
    const Pds3Value* column_name = o.find("NAME");
    if (!column_name) throw SceneError(name + ":" + std::to_string(o.line) + ": a COLUMN without a NAME");
    const Role role = role_of(column_name->text);
    if (role == Role::kOther) continue;
    Column c{column_name->text, whole(o, "START_BYTE") - 1, whole(o, "BYTES")};
    if (c.start + c.bytes > row_bytes)
      throw SceneError(name + ":" + std::to_string(o.line) + ": column " + c.name + " ends past the row's " +
                       std::to_string(row_bytes) + " bytes");
    auto& slot = columns[static_cast<int>(role)];
    if (slot) throw SceneError(name + ":" + std::to_string(o.line) + ": two columns read as one (" + slot->name +
                               " and " + c.name + ")");
    slot = c;
  }
  for (const auto& [role, what] : {std::pair{Role::kDegree, "DEGREE"}, std::pair{Role::kOrder, "ORDER"},
                                  std::pair{Role::kC, "C"}, std::pair{Role::kS, "S"}})
    if (!columns[static_cast<int>(role)])
      throw SceneError(name + ":" + std::to_string(table->line) + ": the TABLE has no " + what +
                       " column (noether reads DEGREE, ORDER, C or CIJ, S or SIJ, and their _UNC if given)");

  StokesFile out;
  out.format = "pds";
  if (const Pds3Value* id = label.find("ORIGINAL_PRODUCT_ID"))
    out.model = id->text;
  else if (const Pds3Value* product = label.find("PRODUCT_ID"))
    out.model = product->text;
  else
    out.model = file.filename().string();
  // What the table does not hold, from the label's free text.
  const Pds3Value* description = label.find("DESCRIPTION");
  const std::string text = description ? description->text : "";
  const std::size_t text_line = description ? description->line : label.line;
  out.reference_radius = stated(text, {"reference radius:"}, false, name, text_line);
  out.gm = stated(text, {"gravitational constant, gm:", "gm:"}, true, name, text_line);
  if (const auto gm_text = after(text, "gm:"); out.gm && gm_text) {  // "+/- 2.19591611330E-09 km^3/s^2" after it
    if (const auto plus_minus = after(gm_text->substr(0, 200), "+/-"))
      if (const auto sigma = quantity(*plus_minus); sigma && sigma->value >= 0)
        out.gm_sigma = sigma->value * (sigma->unit.rfind("km", 0) == 0 || sigma->unit.rfind("KM", 0) == 0 ? 1e9 : 1.0);
  }
  int degree = -1;
  if (const auto d = after(text, "degree:")) {
    const auto q = quantity(*d);
    if (!q || q->value != std::floor(q->value) || q->value < 1 || q->value > kMaxFileDegree)
      throw SceneError(name + ":" + std::to_string(text_line) + ": its DESCRIPTION's 'Degree:' is not a degree");
    degree = static_cast<int>(q->value);
  }
  if (const auto normalized = after(text, "coefficients normalized:")) {
    const std::vector<std::string> words = fields(normalized->substr(0, normalized->find('\n')));
    const std::string word = words.empty() ? "" : pds3_upper(words[0]);
    if (word == "YES") out.normalized = true;
    else if (word == "NO") out.normalized = false;
  }
  if (!out.gm) out.defects.push_back(name + ": the label states no GM: the body's 'mass' must give it");
  if (!out.reference_radius)
    out.defects.push_back(name + ": the label states no reference radius: gravity.reference_radius must give it");
  if (!out.normalized)
    out.defects.push_back(name + ": the label does not say whether the coefficients are normalized: "
                          "gravity.normalized must");

  // The table: ROWS records of ROW_BYTES, each column where the label puts it.
  const Pds3Pointer pointer = pds3_pointer(label, "^TABLE", file);
  const std::filesystem::path tab = pointer.file;
  const std::size_t record_bytes =
      label.find("RECORD_BYTES") ? whole(label, "RECORD_BYTES") : row_bytes;
  const std::size_t first = (pointer.record - 1) * record_bytes;  // where the table starts in its file
  constexpr std::uintmax_t kMaxBytes = std::uintmax_t{1} << 30;  // as read_stokes_file's
  const std::string data = read_pds3_file(tab, kMaxBytes);
  if (data.size() < first + rows * row_bytes)
    throw SceneError(tab.string() + ": " + std::to_string(data.size()) + " bytes, short of the " +
                     std::to_string(rows) + " rows of " + std::to_string(row_bytes) + " bytes its label (" + name +
                     ") declares: the file is cut short; fetch it whole again");
  if (first == 0 && data.size() > rows * row_bytes)
    out.defects.push_back(tab.string() + ": " + std::to_string(data.size() - rows * row_bytes) +
                          " bytes past the label's " + std::to_string(rows) + " rows, not read");
  Rows read;
  const std::string tab_name = tab.string();
  for (std::size_t r = 0; r < rows; ++r) {
    const Where where{tab_name, first / record_bytes + r + 1};
    auto cell = [&](Role role) {
      const Column& c = *columns[static_cast<int>(role)];
      return trim(data.substr(first + r * row_bytes + c.start, c.bytes));
    };
    const int n = integer(cell(Role::kDegree), where, "degree");
    const int m = integer(cell(Role::kOrder), where, "order");
    double C = number(cell(Role::kC), where, "C"), S = number(cell(Role::kS), where, "S");
    if (n == 1 && std::max(std::abs(C), std::abs(S)) > 1.0) {
      // NLR393V3's first row holds −119.356 as C(1, 0): no normalized coefficient is that large.
      char text_out[240];
      std::snprintf(text_out, sizeof text_out,
                    "%s:%zu: degree 1, order %d holds C = %.12g, S = %.12g: not a normalized coefficient (|C| > 1); "
                    "read as 0 (a field about the centre of mass)",
                    tab_name.c_str(), r + 1, m, C, S);
      out.defects.push_back(text_out);
      C = S = 0.0;
    }
    if (degree >= 0 && n > degree)
      throw SceneError(where() + "degree " + std::to_string(n) + " is above the label's " + std::to_string(degree));
    read.add(n, m, C, S, where);
    if (columns[static_cast<int>(Role::kSigmaC)] && columns[static_cast<int>(Role::kSigmaS)])
      read.sigmas[{n, m}] = {number(cell(Role::kSigmaC), where, "σC"), number(cell(Role::kSigmaS), where, "σS")};
  }
  if (degree < 0) {
    degree = read.values.empty() ? 0 : read.values.rbegin()->first.first;
    out.defects.push_back(name + ": the label states no degree: read to the table's last, " + std::to_string(degree));
  }
  out.coefficients = read.build(degree, tab_name);
  stops_short(read, degree, tab_name, "the label's degree");
  if (!read.sigmas.empty()) {
    const auto size = out.coefficients.C.size();
    out.sigma_C.assign(size, 0.0);
    out.sigma_S.assign(size, 0.0);
    for (const auto& [nm, sigma] : read.sigmas) {
      const auto k = static_cast<std::size_t>(StokesCoefficients::index(nm.first, nm.second));
      out.sigma_C[k] = sigma.first, out.sigma_S[k] = sigma.second;
    }
  }
  return out;
}

}  // namespace noether
