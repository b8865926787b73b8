#pragma once
// The scene's schema: every key a scene may hold, one table per section (the scene's top level,
// a body, its orbit, its shape, run, run.trust, particles, ...), each key with its type, the
// scene unit it is read in, its default and one line of doc. The tables drive:
//   - the key checks: an unknown key is named with the closest known one ("did you mean") and
//     the section that does have it; a missing required key is named with its doc; a number,
//     integer, flag, text or [x, y, z] of the wrong form is refused at its line;
//   - the defaults: a section's readers (number, integer, flag, text) take an absent key's value
//     from its row, not from a literal of their own;
//   - docs/user-guide.md "Scene reference", which is scene_reference_markdown()'s output
//     (test SceneSchema.DocumentedInUserGuide).
// The readers of the sections (bodies.cpp, initial_state.cpp, run_settings.cpp, particles.cpp,
// ...) check what a table cannot say: ranges, combinations of keys, files, names of bodies.
#include <noether/params.hpp>

#include <span>
#include <string>
#include <string_view>

namespace noether::detail {

// What a key's value is. number, integer, flag, text, file, body and vector are checked when the
// section's keys are; a list, a mapping, a plugin or several forms by the section's reader, which
// says what it expected.
enum class KeyType {
  number,   // a finite number
  integer,  // a whole number
  flag,     // true or false
  text,     // a word or a string
  file,     // a file name, relative to the scene's folder
  body,     // a body's name
  vector,   // [x, y, z]
  pair,     // two numbers
  matrix,   // [[a, b, c], [d, e, f], [g, h, i]]
  list,     // a list (of the items its section describes)
  mapping,  // a mapping (its section)
  plugin,   // {plugin: NAME, ...the plugin's keys}: `noether plugins`
  forms,    // one of several forms, which the doc line names
};

// The scene unit a value is read in (docs/user-guide.md "Units"): the declared units' length,
// mass and time, or the scene's own.
enum class SceneUnit {
  none,
  length,
  mass,
  time,
  velocity,
  density,
  inertia,
  angular_velocity,
  angular_momentum,
  degrees,
  gravitational_constant,
};

struct SceneKey {
  std::string_view key;
  KeyType type = KeyType::number;
  SceneUnit unit = SceneUnit::none;
  bool required = false;
  // The value of an absent key as YAML text, which the readers use ("": none, and `absent` says
  // what absence means, e.g. "the lightest body").
  std::string_view otherwise{};
  std::string_view absent{};
  std::string_view doc{};
  // The section that describes the value's own keys (a mapping's, a list's items'), if any.
  std::string_view section{};
};

struct SceneSection {
  std::string_view path;   // "" (the scene's top level), "bodies[]", "run.trust", ...
  std::string_view about;  // one line for the reference
  std::span<const SceneKey> keys;

  // The row of `key`; std::logic_error for a key the table lacks (a reader's mistake).
  const SceneKey& row(std::string_view key) const;
  // Checks `node`'s keys (above); `what` names the node in messages ("body 'moon'", "'run'").
  void check(const Params& node, const std::string& what) const;
  // `key`'s value in `node`, else the row's default (std::logic_error if it has none).
  double number(const Params& node, std::string_view key) const;
  long integer(const Params& node, std::string_view key) const;
  bool flag(const Params& node, std::string_view key) const;
  std::string text(const Params& node, std::string_view key) const;
};

// Every section, in the reference's order.
std::span<const SceneSection> scene_sections();
// The section at `path`; std::logic_error if none.
const SceneSection& scene_section(std::string_view path);

// The reference tables of docs/user-guide.md, as markdown.
std::string scene_reference_markdown();

}  // namespace noether::detail
