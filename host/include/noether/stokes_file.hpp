#pragma once
// Gravity-field files: Stokes coefficients as missions publish them (docs/gravity-fields.md).
//   icgem  ICGEM's .gfc (a header of keywords ended by end_of_head, then `gfc L M C S [σC σS]`
//          lines; GM in m³/s², the reference radius in m; `norm` fully_normalized by default)
//   shadr  the Planetary Data System's spherical-harmonic ASCII data record (.tab): one
//          comma-separated header record — reference radius (km), GM (km³/s²), σ(GM), degree,
//          order, normalization state (1 = normalized), reference longitude and latitude — then
//          `n, m, C, S, σC, σS` records
//   table  `n m C S` rows (commas or blanks, '#' comments) with nothing else: the reference
//          radius, the normalization and the mass come from the scene
// Missing coefficients are zero, C00 is 1 when absent (the central term is the GM); degree-1
// coefficients must vanish (a centre-of-mass frame; below 1e-12 they are taken as the round-off
// they are). Errors name the file and line.
#include <noether/stokes_coefficients.hpp>

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

namespace noether {

struct StokesFile {
  std::string format;  // icgem, shadr or table
  std::string model;   // ICGEM's modelname, SHADR's file name, or ""
  // As the file states them, in SI (m³/s², m): absent for a table.
  std::optional<double> gm, reference_radius;
  std::optional<bool> normalized;
  // The coefficients to the file's degree (mass and reference radius left for the caller:
  // reference_radius in metres when the file states it).
  StokesCoefficients coefficients;
};

// The format a file's name suggests: .gfc → icgem, .tab/.TAB → shadr, otherwise "" (say which).
std::string stokes_format_of(const std::filesystem::path& file);

// Reads `file` as `format`; a static field only (ICGEM's time-variable gfct/trnd/acos/asin
// lines are refused). Throws SceneError naming file and line.
StokesFile read_stokes_file(const std::filesystem::path& file, const std::string& format);

// Writes cs as an ICGEM .gfc file (errors: no), GM in m³/s² and the reference radius in m
// given in SI; `comments` go before the header, one line each.
void write_icgem(std::ostream& out, const StokesCoefficients& cs, double gm_si, double reference_radius_si,
                 const std::string& model, const std::vector<std::string>& comments);

// Writes cs as a table (`# n m C S`), reference radius and normalization in comment lines.
void write_stokes_table(std::ostream& out, const StokesCoefficients& cs, const std::vector<std::string>& comments);

}  // namespace noether
