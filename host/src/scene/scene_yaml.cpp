// Scene text → Params: YAML read with every node's "file:line", expansion limits against alias
// bombs, --set overrides, and back to YAML (scene_as_run). parse_scene (scene.cpp) builds the
// scene from the tree.
#include "scene/scene_yaml.hpp"

#include <noether/error.hpp>
#include <noether/scene.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace noether {

namespace {

// The most values a document may expand to. YAML aliases are shared, not copied, by the
// parser; expanding them here is where a few lines (an "alias bomb") could take gigabytes.
// Beyond kFreeExpansion values, a document may also expand to at most kMaxExpansionRatio
// times the values it writes: aliases that repeat a body's inertia are fine, aliases repeated
// within aliases are not.
constexpr std::size_t kMaxValues = 1'000'000;
constexpr std::size_t kFreeExpansion = 100'000;
constexpr std::size_t kMaxExpansionRatio = 100;

// YAML → Params, keeping "file:line" of every node; `budget` counts the values left.
Params to_params(const YAML::Node& node, const std::string& file, std::size_t& budget) {
  const std::string where =
      node.Mark().line >= 0 ? file + ":" + std::to_string(node.Mark().line + 1) : file;
  if (budget-- == 0)
    throw SceneError(where + ": the document expands to more than " + std::to_string(kMaxValues) +
                     " values (aliases repeated within aliases?); noether refuses it");
  switch (node.Type()) {
    case YAML::NodeType::Scalar: return Params::scalar(node.Scalar(), where);
    case YAML::NodeType::Sequence: {
      std::vector<Params> items;
      for (const auto& item : node) items.push_back(to_params(item, file, budget));
      return Params::sequence(std::move(items), where);
    }
    case YAML::NodeType::Map: {
      std::vector<std::pair<std::string, Params>> entries;
      for (const auto& kv : node) {
        if (!kv.first.IsScalar())
          throw SceneError(file + ":" + std::to_string(kv.first.Mark().line + 1) +
                           ": a key must be a plain name, not a list or a mapping");
        const std::string key = kv.first.Scalar();
        for (const auto& e : entries)
          if (e.first == key)
            throw SceneError(file + ":" + std::to_string(kv.first.Mark().line + 1) +
                             ": key '" + key + "' appears twice");
        entries.emplace_back(key, to_params(kv.second, file, budget));
      }
      return Params::map(std::move(entries), where);
    }
    default: return Params::scalar("", where);  // an empty value
  }
}

// The number of values `node` expands to, counted without expanding anything: an alias is the
// anchored node itself (it carries the anchor's position), so each distinct node is counted
// once and its count reused wherever it is repeated (`written` counts the values visited, not
// repeated). Stops past `limit`; `line` is then the line of the first (innermost) node found to
// exceed it. An alias inside the node it names (a
// cycle, which yaml-cpp accepts) and nesting deeper than kMaxDepth are refused.
constexpr int kMaxDepth = 200;
constexpr std::size_t kCounting = std::numeric_limits<std::size_t>::max();
using SizeMemo = std::map<std::pair<std::size_t, int>, std::size_t>;
struct Expansion {
  SizeMemo memo;
  std::size_t written = 0;  // values visited once (not through a repeated alias)
  int line = -1;
};
std::size_t expanded_size(const YAML::Node& node, const std::string& file, Expansion& e, std::size_t limit,
                          int depth = 0) {
  SizeMemo& memo = e.memo;
  const YAML::Mark mark = node.Mark();
  if (depth > kMaxDepth)
    throw SceneError(file + ":" + std::to_string(mark.line + 1) + ": values nested deeper than " +
                     std::to_string(kMaxDepth) + " levels; noether refuses the document");
  if (!node.IsSequence() && !node.IsMap()) {
    ++e.written;
    return 1;
  }
  const std::pair<std::size_t, int> key{static_cast<std::size_t>(mark.pos), static_cast<int>(node.Type())};
  if (mark.pos >= 0) {
    if (const auto found = memo.find(key); found != memo.end()) {
      if (found->second == kCounting)
        throw SceneError(file + ":" + std::to_string(mark.line + 1) +
                         ": an alias refers to a value that contains it (an endless document); noether refuses it");
      return found->second;
    }
    memo[key] = kCounting;
  }
  ++e.written;
  std::size_t n = 1;
  if (node.IsSequence()) {
    for (const auto& item : node)
      if ((n += expanded_size(item, file, e, limit, depth + 1)) > limit) break;
  } else {
    for (const auto& kv : node)
      if ((n += expanded_size(kv.second, file, e, limit, depth + 1)) > limit) break;
  }
  n = std::min(n, limit + 1);
  if (n > limit && e.line < 0) e.line = mark.line;
  if (mark.pos >= 0) memo[key] = n;
  return n;
}

}  // namespace

Params parse_yaml(const std::string& text, const std::string& file) {
  try {
    const YAML::Node document = YAML::Load(text);
    Expansion expansion;
    const std::size_t values = expanded_size(document, file, expansion, kMaxValues);
    if (values > kMaxValues)
      throw SceneError(file + ":" + std::to_string(expansion.line + 1) + ": the document expands to more than " + std::to_string(kMaxValues) +
                       " values (aliases repeated within aliases?); noether refuses it");
    if (values > kFreeExpansion && values > kMaxExpansionRatio * expansion.written)
      throw SceneError(file + ": aliases expand the document's " + std::to_string(expansion.written) +
                       " values to " + std::to_string(values) + ", more than " + std::to_string(kMaxExpansionRatio) +
                       " times (aliases repeated within aliases?); noether refuses it");
    std::size_t budget = kMaxValues;  // the same bound, kept while expanding
    return to_params(document, file, budget);
  } catch (const YAML::Exception& e) {  // a parse error, or anything else yaml-cpp refuses
    std::ostringstream msg;
    msg << file << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
        << ": malformed YAML: " << e.msg;
    throw SceneError(msg.str());
  }
}

namespace {

// An index into a list: digits only, and short enough to be one.
bool is_index(const std::string& part, std::size_t size) {
  return !part.empty() && part.size() <= 9 && part.find_first_not_of("0123456789") == std::string::npos &&
         std::stoul(part) < size;
}

// The item of a list named by parts[i..]: an index, or a body's name (a name with dots spans
// several parts: the longest that names one is taken; `i` moves to its last part).
Params* list_item(std::vector<Params>& items, const std::vector<std::string>& parts, std::size_t& i) {
  if (is_index(parts[i], items.size())) return &items[std::stoul(parts[i])];
  for (std::size_t j = parts.size(); j-- > i;) {
    std::string name = parts[i];
    for (std::size_t k = i + 1; k <= j; ++k) name += "." + parts[k];
    for (auto& item : items)
      if (item.is_map() && item.has("name") && item.at("name").is_scalar() && item.at("name").as_string() == name) {
        i = j;
        return &item;
      }
  }
  return nullptr;
}

// "; did you mean 'x'?" for a key of a mapping or a body name of a list, when one is close.
std::string suggestion(const Params& node, const std::string& word) {
  std::vector<std::string> candidates;
  if (node.is_map())
    for (const auto& [key, value] : node.entries()) candidates.push_back(key);
  if (node.is_sequence())
    for (const auto& item : node.items())
      if (item.is_map() && item.has("name") && item.at("name").is_scalar()) candidates.push_back(item.at("name").as_string());
  const std::string near = closest_match(word, candidates);
  return near.empty() ? "" : "; did you mean '" + near + "'?";
}

}  // namespace

// "--set KEY=VALUE" sets (or replaces) a value, "--set KEY+=VALUE" appends VALUE to the list at
// KEY (e.g. a body: bodies+={name: probe, ...}), "--set KEY=~" deletes KEY (a mapping's key, or
// a list's item by index or body name). Edits the tree in place. A body's mass or density
// replaces the other one the scene gives (a shaped body's mass derives its density).
void apply_override(Params& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("--set '" + assignment + "': expected key=value, key+=value (append to a list) or key=~ "
                     "(delete), e.g. integrator.step=1e-3");
  const bool append = assignment[eq - 1] == '+';
  std::string key = assignment.substr(0, append ? eq - 1 : eq);
  if (append && !key.empty() && key.back() == '.') key.pop_back();  // bodies.+=… reads as bodies+=…
  const std::string text = assignment.substr(eq + 1);
  const std::string where = "--set " + key;
  if (key.empty()) throw SceneError("--set '" + assignment + "': no key before '" + (append ? "+=" : "=") + "'");
  Params value = parse_yaml(text, where);
  std::string word = text;  // YAML's null, "~" or "null": delete
  word.erase(0, word.find_first_not_of(" \t"));
  word.erase(word.find_last_not_of(" \t") + 1);
  const bool erase = !append && (word == "~" || word == "null" || word == "Null" || word == "NULL");
  if (value.is_null()) value = Params::scalar("", where);

  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  // The node holding the last part.
  Params* node = &root;
  const std::size_t last = parts.size() - 1;
  for (std::size_t i = 0; i < last; ++i) {
    const std::string& part = parts[i];
    Params* next = nullptr;
    if (node->is_map()) {
      next = node->find(part);
      if (!next && !erase) {  // an optional mapping the scene leaves out (run.trust): made here; a
                              // misspelt key is refused by the scene's key checks
        node->set(part, Params::map({}, where));
        next = node->find(part);
      }
    } else if (node->is_sequence()) {
      std::size_t j = i;
      next = list_item(node->mutable_items(), parts, j);
      if (next && j >= last) {  // a dotted name runs to the end: the whole item
        auto& items = node->mutable_items();
        if (append)
          throw SceneError("--set " + key + "+=: '" + key + "' is not a list (+= appends to a list; = replaces)");
        if (erase)
          items.erase(items.begin() + (next - items.data()));
        else
          *next = std::move(value);
        return;
      }
      i = j;
    }
    if (!next) {
      std::string at;  // the key up to here
      for (std::size_t k = 0; k < i; ++k) at += (k ? "." : "") + parts[k];
      throw SceneError("--set " + key + ": the scene has no '" + part + "' at '" + (at.empty() ? "top level" : at) +
                       "'" + suggestion(*node, part));
    }
    node = next;
  }
  const std::string& name = parts[last];
  if (node->is_sequence()) {  // one item of a list: velocity.1=0.17, or bodies.probe=~
    auto& items = node->mutable_items();
    std::size_t j = last;
    Params* item = list_item(items, parts, j);
    if (item && erase) {
      items.erase(items.begin() + (item - items.data()));
      return;
    }
    if (item && !append) {
      *item = std::move(value);
      return;
    }
    if (item && append && item->is_sequence()) {
      item->mutable_items().push_back(std::move(value));
      return;
    }
    throw SceneError("--set " + key + ": '" + key.substr(0, key.size() - name.size() - 1) + "' has no item '" +
                     name + "' (it has " + std::to_string(items.size()) + ", numbered from 0" +
                     (items.size() > 0 && items[0].is_map() && items[0].has("name") ? ", or by name" : "") + ")" +
                     suggestion(*node, name));
  }
  if (!node->is_map() && !node->is_null())
    throw SceneError("--set " + key + ": '" + node->path() + "' is not a mapping");
  if (erase) {
    if (!node->is_map() || !node->has(name))
      throw SceneError("--set " + key + "=~: the scene has no '" + key + "' to delete");
    node->erase(name);
    return;
  }
  if (append) {
    Params* list = node->is_map() ? node->find(name) : nullptr;
    if (list && !list->is_sequence())
      throw SceneError("--set " + key + "+=: '" + key + "' is not a list (+= appends to a list; = replaces)");
    if (!list) {
      node->set(name, Params::sequence({}, where));
      list = node->find(name);
    }
    list->mutable_items().push_back(std::move(value));
    return;
  }
  // A body's mass or density replaces the other (the scene's density, when a run varies the mass).
  if (node->is_map() && parts.size() >= 3 && parts[0] == "bodies") {
    if (name == "mass") node->erase("density");
    if (name == "density") node->erase("mass");
  }
  node->set(name, std::move(value));
}
namespace {
std::string read_file(const std::filesystem::path& file, const char* what) {
  std::ifstream in(file);
  if (!in) throw SceneError(file.string() + ": cannot open the " + what);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}
}  // namespace

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  return parse_scene(read_file(file, "scene file"), file.string(), overrides);
}

Params parse_params(const std::string& text, const std::string& file) {
  Params p = parse_yaml(text, file);
  p.set_path("");
  return p;
}

Params load_params_file(const std::filesystem::path& file) {
  return parse_params(read_file(file, "file"), file.string());
}

namespace {

void emit(YAML::Emitter& out, const Params& p) {
  if (p.is_scalar()) {
    out << p.as_string();
  } else if (p.is_sequence()) {  // [x, y, z] on one line; a list of mappings (bodies) in blocks
    bool mappings = false;
    for (const auto& item : p.items()) mappings = mappings || item.is_map();
    if (!mappings) out << YAML::Flow;
    out << YAML::BeginSeq;
    for (const auto& item : p.items()) emit(out, item);
    out << YAML::EndSeq;
  } else if (p.is_map()) {
    out << YAML::BeginMap;
    for (const auto& [key, value] : p.entries()) {
      out << YAML::Key << key << YAML::Value;
      emit(out, value);
    }
    out << YAML::EndMap;
  } else {
    out << YAML::Null;
  }
}

}  // namespace

std::string scene_as_run(const Scene& scene) {
  YAML::Emitter out;
  emit(out, scene.root);
  return std::string(out.c_str()) + "\n";
}
}  // namespace noether
