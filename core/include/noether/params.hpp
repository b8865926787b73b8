#pragma once
// Params: a small parameter tree owned by core, so that plugins read their own settings
// without depending on the YAML library's ABI. Every node remembers where it came from
// ("file:line") so errors point at the field a user must change.
#include <string>
#include <utility>
#include <vector>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class Params {
 public:
  enum class Kind { Null, Scalar, Sequence, Map };

  Params() = default;
  static Params scalar(std::string value, std::string where = {});
  static Params sequence(std::vector<Params> items, std::string where = {});
  static Params map(std::vector<std::pair<std::string, Params>> entries, std::string where = {});

  Kind kind() const { return kind_; }
  bool is_null() const { return kind_ == Kind::Null; }
  bool is_scalar() const { return kind_ == Kind::Scalar; }
  bool is_sequence() const { return kind_ == Kind::Sequence; }
  bool is_map() const { return kind_ == Kind::Map; }

  // "file:line" of this node, or "" when made in code.
  const std::string& where() const { return where_; }
  // The dotted path of this node in its tree, e.g. "integrator.step" (for messages).
  const std::string& path() const { return path_; }

  // Scalars. Each throws SceneError naming where() and path() if the value does not fit.
  const std::string& as_string() const;
  double as_double() const;
  long as_int() const;
  bool as_bool() const;
  std::vector<double> as_doubles() const;  // a sequence of numbers

  // Sequences.
  const std::vector<Params>& items() const;
  std::size_t size() const;

  // Maps.
  bool has(const std::string& key) const;
  const Params& at(const std::string& key) const;  // throws SceneError "missing key"
  const std::vector<std::pair<std::string, Params>>& entries() const;
  double get(const std::string& key, double fallback) const;
  long get(const std::string& key, long fallback) const;
  std::string get(const std::string& key, const std::string& fallback) const;
  bool get(const std::string& key, bool fallback) const;
  // Sets or replaces a key (used by --set overrides and by code that builds parameters).
  void set(const std::string& key, Params value);
  // Mutable access for code that edits a tree (overrides): nullptr if absent.
  Params* find(const std::string& key);
  std::vector<Params>& mutable_items();
  // Removes a key if present.
  void erase(const std::string& key);

  // Throws SceneError for the first key not in `allowed`, suggesting the closest allowed key.
  void check_keys(const std::vector<std::string>& allowed, const std::string& what) const;

  // "file:line: " prefix for messages about this node (empty if unknown).
  std::string here() const;

  // Re-roots the dotted paths of this subtree (called by the scene reader).
  void set_path(const std::string& path);

 private:
  Kind kind_ = Kind::Null;
  std::string scalar_;
  std::vector<Params> items_;
  std::vector<std::pair<std::string, Params>> entries_;
  std::string where_;
  std::string path_;
};

// Edit distance, for "did you mean" suggestions.
std::size_t edit_distance(const std::string& a, const std::string& b);
// The closest candidate to `word`, or "" if none is reasonably close.
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace noether

namespace noether {

// The where() of a value the host filled in from a plugin's documented default (ParamDoc).
inline constexpr const char* kPluginDefault = "the plugin's documented default";
// Whether the scene gave `key` (not the host from the plugin's ParamDoc default).
inline bool given(const Params& params, const std::string& key) {
  return params.has(key) && params.at(key).where() != kPluginDefault;
}

}  // namespace noether

#pragma GCC visibility pop
