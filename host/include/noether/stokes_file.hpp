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
//   pds    a PDS3 label (.lbl) and the fixed-length table it describes (pds_stokes.cpp): the
//          columns by the label's NAME, START_BYTE and BYTES, the 1σ columns kept; the degree,
//          normalization, reference radius and GM from the label's DESCRIPTION (NEAR's Eros
//          fields); real files' defects read as they are and named
// A file whose coefficients stop short of the degree it declares is refused (a truncated file).
// Missing coefficients are zero, C00 is 1 when absent (the central term is the GM); degree-1
// coefficients must vanish (a centre-of-mass frame; below 1e-12 they are taken as the round-off
// they are). Errors name the file and line.
#include <noether/stokes_coefficients.hpp>

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace noether {

struct StokesFile {
  std::string format;  // icgem, shadr, table or pds
  std::string model;   // ICGEM's modelname, SHADR's file name, or ""
  // As the file states them, in SI (m³/s², m): absent for a table.
  std::optional<double> gm, reference_radius;
  std::optional<bool> normalized;
  // The coefficients to the file's degree (mass and reference radius left for the caller:
  // reference_radius in metres when the file states it).
  StokesCoefficients coefficients;
  // The coefficients' 1σ, indexed as C and S, where the file gives them (else empty), and GM's.
  std::vector<double> sigma_C, sigma_S;
  std::optional<double> gm_sigma;
  // What is wrong with the file as archived, read as it is (a pds label's missing statements, a
  // row that is no coefficient): one message each, naming the file and line.
  std::vector<std::string> defects;
};

// The format a file's name suggests: .gfc → icgem, .lbl → pds, .tab → pds when a label of its
// name lies beside it, else shadr; otherwise "" (say which).
std::string stokes_format_of(const std::filesystem::path& file);

// Reads `file` as `format`; a static field only (ICGEM's time-variable gfct/trnd/acos/asin
// lines are refused). Throws SceneError naming file and line.
StokesFile read_stokes_file(const std::filesystem::path& file, const std::string& format);

// Reads a PDS3 label and the table it describes (format pds). Throws SceneError.
StokesFile read_pds_stokes(const std::filesystem::path& label);

// Writes cs as an ICGEM .gfc file (errors: no), GM in m³/s² and the reference radius in m
// given in SI; `comments` go before the header, one line each.
void write_icgem(std::ostream& out, const StokesCoefficients& cs, double gm_si, double reference_radius_si,
                 const std::string& model, const std::vector<std::string>& comments);

// Writes cs as a table (`# n m C S`), reference radius and normalization in comment lines.
void write_stokes_table(std::ostream& out, const StokesCoefficients& cs, const std::vector<std::string>& comments);

}  // namespace noether
