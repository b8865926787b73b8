#include <noether/error.hpp>
#include <noether/params.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace noether {

Params Params::scalar(std::string value, std::string where) {
  Params p;
  p.kind_ = Kind::Scalar;
  p.scalar_ = std::move(value);
  p.where_ = std::move(where);
  return p;
}

Params Params::sequence(std::vector<Params> items, std::string where) {
  Params p;
  p.kind_ = Kind::Sequence;
  p.items_ = std::move(items);
  p.where_ = std::move(where);
  return p;
}

Params Params::map(std::vector<std::pair<std::string, Params>> entries, std::string where) {
  Params p;
  p.kind_ = Kind::Map;
  p.entries_ = std::move(entries);
  p.where_ = std::move(where);
  return p;
}

std::string Params::here() const { return where_.empty() ? std::string() : where_ + ": "; }

namespace {
std::string field(const Params& p) {
  return p.path().empty() ? std::string("value") : "'" + p.path() + "'";
}
}  // namespace

const std::string& Params::as_string() const {
  if (kind_ != Kind::Scalar)
    throw SceneError(here() + field(*this) + " must be a single value");
  return scalar_;
}

double Params::as_double() const {
  const std::string& s = as_string();
  double v = 0.0;
  const char* first = s.data();
  const char* last = s.data() + s.size();
  if (!s.empty() && *first == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || !std::isfinite(v))
    throw SceneError(here() + field(*this) + " must be a finite number, not '" + s + "'");
  return v;
}

long Params::as_int() const {
  const double v = as_double();
  if (v != std::floor(v) || std::abs(v) > 9e15)
    throw SceneError(here() + field(*this) + " must be an integer, not '" + scalar_ + "'");
  return static_cast<long>(v);
}

bool Params::as_bool() const {
  const std::string& s = as_string();
  if (s == "true" || s == "True" || s == "yes" || s == "on") return true;
  if (s == "false" || s == "False" || s == "no" || s == "off") return false;
  throw SceneError(here() + field(*this) + " must be true or false, not '" + s + "'");
}

std::vector<double> Params::as_doubles() const {
  if (kind_ != Kind::Sequence)
    throw SceneError(here() + field(*this) + " must be a list of numbers, e.g. [1, 0, 0]");
  std::vector<double> v;
  v.reserve(items_.size());
  for (const auto& item : items_) v.push_back(item.as_double());
  return v;
}

const std::vector<Params>& Params::items() const {
  if (kind_ != Kind::Sequence) throw SceneError(here() + field(*this) + " must be a list");
  return items_;
}

std::size_t Params::size() const {
  return kind_ == Kind::Sequence ? items_.size() : kind_ == Kind::Map ? entries_.size() : 0;
}

bool Params::has(const std::string& key) const {
  if (kind_ != Kind::Map) return false;
  return std::any_of(entries_.begin(), entries_.end(),
                     [&](const auto& e) { return e.first == key; });
}

const Params& Params::at(const std::string& key) const {
  if (kind_ != Kind::Map)
    throw SceneError(here() + field(*this) + " must be a mapping with key '" + key + "'");
  for (const auto& e : entries_)
    if (e.first == key) return e.second;
  const std::string full = path_.empty() ? key : path_ + "." + key;
  throw SceneError(here() + "missing key '" + full + "'");
}

const std::vector<std::pair<std::string, Params>>& Params::entries() const {
  if (kind_ != Kind::Map) throw SceneError(here() + field(*this) + " must be a mapping");
  return entries_;
}

double Params::get(const std::string& key, double fallback) const {
  return has(key) ? at(key).as_double() : fallback;
}
long Params::get(const std::string& key, long fallback) const {
  return has(key) ? at(key).as_int() : fallback;
}
std::string Params::get(const std::string& key, const std::string& fallback) const {
  return has(key) ? at(key).as_string() : fallback;
}
bool Params::get(const std::string& key, bool fallback) const {
  return has(key) ? at(key).as_bool() : fallback;
}

void Params::set(const std::string& key, Params value) {
  if (kind_ == Kind::Null) kind_ = Kind::Map;
  if (kind_ != Kind::Map) throw SceneError(here() + field(*this) + " is not a mapping");
  value.set_path(path_.empty() ? key : path_ + "." + key);
  for (auto& e : entries_)
    if (e.first == key) {
      e.second = std::move(value);
      return;
    }
  entries_.emplace_back(key, std::move(value));
}

Params* Params::find(const std::string& key) {
  if (kind_ != Kind::Map) return nullptr;
  for (auto& e : entries_)
    if (e.first == key) return &e.second;
  return nullptr;
}

std::vector<Params>& Params::mutable_items() {
  if (kind_ != Kind::Sequence) throw SceneError(here() + field(*this) + " must be a list");
  return items_;
}

void Params::erase(const std::string& key) {
  std::erase_if(entries_, [&](const auto& e) { return e.first == key; });
}

void Params::check_keys(const std::vector<std::string>& allowed, const std::string& what) const {
  for (const auto& [key, value] : entries()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::ostringstream msg;
    msg << value.here() << "unknown key '" << key << "' in " << what;
    const std::string guess = closest_match(key, allowed);
    if (!guess.empty()) msg << " (did you mean '" << guess << "'?)";
    msg << "; allowed keys:";
    for (const auto& a : allowed) msg << ' ' << a;
    throw SceneError(msg.str());
  }
}

void Params::set_path(const std::string& path) {
  path_ = path;
  for (std::size_t i = 0; i < items_.size(); ++i)
    items_[i].set_path(path + "." + std::to_string(i));
  for (auto& [key, value] : entries_) value.set_path(path.empty() ? key : path + "." + key);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

}  // namespace noether
