// Gravity-field files: ICGEM .gfc, PDS SHADR and plain tables (stokes_file.hpp).
#include <noether/error.hpp>
#include <noether/pds3_label.hpp>
#include <noether/stokes_file.hpp>

#include "scene/stokes_rows.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace noether {

namespace {

using namespace detail;  // Where, fields, number, integer, Rows (stokes_rows.hpp)

StokesFile read_icgem(std::istream& in, const std::string& file) {
  StokesFile out;
  out.format = "icgem";
  Where where{file, 0};
  std::map<std::string, std::pair<std::string, std::size_t>> header;
  std::string line;
  bool in_data = false;
  Rows rows;
  while (std::getline(in, line)) {
    ++where.line;
    const std::vector<std::string> f = fields(line);
    if (f.empty()) continue;
    if (!in_data) {
      if (f[0] == "end_of_head") {
        in_data = true;
      } else if (f.size() >= 2 && f[0] != "begin_of_head") {
        header.emplace(f[0], std::pair{trim(line.substr(line.find(f[0]) + f[0].size())), where.line});
      }
      continue;
    }
    const std::string& key = f[0];
    if (key == "gfct" || key == "trnd" || key == "dot" || key == "acos" || key == "asin")
      throw SceneError(where() + "a time-variable term ('" + key + "'): noether reads static fields (gfc lines) only");
    if (key != "gfc") throw SceneError(where() + "unknown line key '" + key + "' (an ICGEM field's lines are 'gfc L M C S')");
    if (f.size() < 5) throw SceneError(where() + "a gfc line needs L M C S");
    rows.add(integer(f[1], where, "degree"), integer(f[2], where, "order"), number(f[3], where, "C"),
             number(f[4], where, "S"), where);
  }
  if (!in_data) throw SceneError(file + ": no 'end_of_head' line: not an ICGEM .gfc file");
  auto value = [&](std::initializer_list<const char*> keys, const std::string& what) -> std::pair<std::string, std::size_t> {
    for (const char* k : keys)
      if (auto it = header.find(k); it != header.end()) return it->second;
    throw SceneError(file + ": the header has no '" + *keys.begin() + "' (" + what + ")");
  };
  auto header_number = [&](std::initializer_list<const char*> keys, const std::string& what) {
    const auto [text, line_no] = value(keys, what);
    return number(fields(text)[0], Where{file, line_no}, what);
  };
  if (auto it = header.find("product_type"); it != header.end() && fields(it->second.first)[0] != "gravity_field")
    throw SceneError(Where{file, it->second.second}() + "product_type '" + it->second.first +
                     "' is not a gravity_field");
  if (auto it = header.find("modelname"); it != header.end()) out.model = it->second.first;
  out.gm = header_number({"earth_gravity_constant", "gravity_constant"}, "GM in m^3/s^2");
  out.reference_radius = header_number({"radius"}, "the reference radius in m");
  if (!(*out.gm > 0.0) || !(*out.reference_radius > 0.0))
    throw SceneError(file + ": the header's GM and radius must be positive");
  out.normalized = true;
  if (auto it = header.find("norm"); it != header.end()) {
    const std::string norm = fields(it->second.first)[0];
    if (norm == "unnormalized")
      out.normalized = false;
    else if (norm != "fully_normalized")
      throw SceneError(Where{file, it->second.second}() + "norm '" + norm + "': expected fully_normalized or unnormalized");
  }
  const auto [degree_text, degree_line] = value({"max_degree"}, "the field's degree");
  const int max_degree = integer(fields(degree_text)[0], Where{file, degree_line}, "max_degree");
  if (!rows.values.empty() && rows.values.rbegin()->first.first > max_degree)
    throw SceneError(Where{file, rows.values.rbegin()->second.second}() + "degree " +
                     std::to_string(rows.values.rbegin()->first.first) + " is above the header's max_degree " +
                     std::to_string(max_degree));
  out.coefficients = rows.build(max_degree, file);
  stops_short(rows, max_degree, file, "the header's max_degree");
  return out;
}

StokesFile read_shadr(std::istream& in, const std::string& file) {
  StokesFile out;
  out.format = "shadr";
  out.model = std::filesystem::path(file).filename().string();
  Where where{file, 0};
  std::string line;
  Rows rows;
  int degree = -1;
  while (std::getline(in, line)) {
    ++where.line;
    const std::vector<std::string> f = fields(line);
    if (f.empty()) continue;
    if (degree < 0) {  // the header record
      if (f.size() < 6)
        throw SceneError(where() + "a SHADR header record needs reference radius (km), GM (km^3/s^2), its "
                         "uncertainty, degree, order and normalization state");
      out.reference_radius = number(f[0], where, "the reference radius (km)") * 1e3;
      out.gm = number(f[1], where, "GM (km^3/s^2)") * 1e9;
      degree = integer(f[3], where, "the degree");
      const double state = number(f[5], where, "the normalization state");
      if (state != 0.0 && state != 1.0)
        throw SceneError(where() + "normalization state " + f[5] + ": expected 1 (normalized) or 0 (unnormalized)");
      out.normalized = state == 1.0;
      for (std::size_t k = 6; k < std::min<std::size_t>(f.size(), 8); ++k)
        if (number(f[k], where, "the reference longitude/latitude") != 0.0)
          throw SceneError(where() + "the expansion's reference longitude and latitude must be 0, not " + f[k]);
      if (!(*out.gm > 0.0) || !(*out.reference_radius > 0.0))
        throw SceneError(where() + "the header's GM and reference radius must be positive");
      continue;
    }
    if (f.size() < 4) throw SceneError(where() + "a coefficient record needs n, m, C, S");
    const int n = integer(f[0], where, "degree");
    if (n > degree)
      throw SceneError(where() + "degree " + std::to_string(n) + " is above the header's " + std::to_string(degree));
    rows.add(n, integer(f[1], where, "order"), number(f[2], where, "C"), number(f[3], where, "S"), where);
  }
  if (degree < 0) throw SceneError(file + ": empty: no SHADR header record");
  out.coefficients = rows.build(degree, file);
  stops_short(rows, degree, file, "the header record's degree");
  return out;
}

StokesFile read_table(std::istream& in, const std::string& file) {
  StokesFile out;
  out.format = "table";
  Where where{file, 0};
  std::string line;
  Rows rows;
  while (std::getline(in, line)) {
    ++where.line;
    const auto hash = line.find('#');
    const std::vector<std::string> f = fields(hash == std::string::npos ? line : line.substr(0, hash));
    if (f.empty()) continue;
    if (f.size() != 4 && f.size() != 6) throw SceneError(where() + "a row needs n m C S (and optionally σC σS)");
    rows.add(integer(f[0], where, "degree"), integer(f[1], where, "order"), number(f[2], where, "C"),
             number(f[3], where, "S"), where);
  }
  out.coefficients = rows.build(-1, file);
  return out;
}

void write_rows(std::ostream& out, const StokesCoefficients& cs, const char* key) {
  char buffer[160];
  for (int n = 0; n <= cs.degree; ++n)
    for (int m = 0; m <= n; ++m) {
      std::snprintf(buffer, sizeof buffer, "%s%5d %4d % .17e % .17e\n", key, n, m, cs.c(n, m), cs.s(n, m));
      out << buffer;
    }
}

}  // namespace

std::string stokes_format_of(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".gfc") return "icgem";
  if (ext == ".lbl") return "pds";
  if (ext == ".tab") return pds3_label_of(file).empty() ? "shadr" : "pds";
  return "";
}

StokesFile read_stokes_file(const std::filesystem::path& file, const std::string& format) {
  if (format == "pds") {  // the label; given the table, its label beside it
    const std::filesystem::path label = pds3_label_of(file);
    return read_pds_stokes(label.empty() ? file : label);
  }
  // A regular file of bounded size (a FIFO or a device such as /dev/zero would be read without end).
  constexpr std::uintmax_t kMaxBytes = std::uintmax_t{1} << 30;
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw SceneError(file.string() + ": the gravity-field file is not a regular file");
  if (const auto bytes = std::filesystem::file_size(file, ec); !ec && bytes > kMaxBytes)
    throw SceneError(file.string() + ": the gravity-field file has " + std::to_string(bytes) +
                     " bytes; noether reads field files of at most 1 GiB");
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot be read");
  if (format == "icgem") return read_icgem(in, file.string());
  if (format == "shadr") return read_shadr(in, file.string());
  if (format == "table") return read_table(in, file.string());
  throw SceneError(file.string() + ": unknown gravity-field format '" + format + "' (icgem, shadr, table or pds)");
}

void write_icgem(std::ostream& out, const StokesCoefficients& cs, double gm_si, double reference_radius_si,
                 const std::string& model, const std::vector<std::string>& comments) {
  for (const std::string& c : comments) out << c << "\n";
  char buffer[160];
  out << "begin_of_head ====================================================================\n";
  out << "product_type              gravity_field\n";
  out << "modelname                 " << model << "\n";
  std::snprintf(buffer, sizeof buffer, "earth_gravity_constant    %.17e\nradius                    %.17e\n", gm_si,
                reference_radius_si);
  out << buffer;
  out << "max_degree                " << cs.degree << "\n";
  out << "errors                    no\n";
  out << "norm                      " << (cs.normalized ? "fully_normalized" : "unnormalized") << "\n";
  out << "tide_system               unknown\n";
  out << "key    L    M             C                        S\n";
  out << "end_of_head ======================================================================\n";
  write_rows(out, cs, "gfc  ");
}

void write_stokes_table(std::ostream& out, const StokesCoefficients& cs, const std::vector<std::string>& comments) {
  for (const std::string& c : comments) out << "# " << c << "\n";
  char buffer[120];
  std::snprintf(buffer, sizeof buffer, "# reference radius %.17g, %s\n# n    m    C    S\n", cs.reference_radius,
                cs.normalized ? "fully normalized" : "unnormalized");
  out << buffer;
  write_rows(out, cs, "");
}

}  // namespace noether
