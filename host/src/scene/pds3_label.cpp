// A PDS3 label as archived (noether/pds3_label.hpp).
#include <noether/error.hpp>
#include <noether/pds3_label.hpp>

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace noether {

const Pds3Value* Pds3Object::find(const std::string& key) const {
  for (const auto& [k, v] : keys)
    if (k == key) return &v;
  return nullptr;
}

const Pds3Object* Pds3Object::object(const std::string& wanted) const {
  for (const Pds3Object& o : objects)
    if (o.name == wanted) return &o;
  return nullptr;
}

namespace {

// Reads the statements of a label's text, character by character, counting lines.
class Reader {
 public:
  Reader(const std::string& text, const std::string& name) : text_(text), name_(name) {}

  Pds3Object label() {
    Pds3Object root;
    root.line = 1;
    std::vector<Pds3Object*> open{&root};
    while (true) {
      skip_blanks();
      if (at_end()) throw error("the label has no END statement (a label cut short?)");
      const std::size_t line = line_;
      const std::string key = word();
      if (key.empty()) throw error(std::string("expected a keyword, not '") + text_[pos_] + "'");
      if (key == "END") {
        skip_blanks_on_line();
        if (open.size() > 1)
          throw error_at(open.back()->line, open.back()->kind + " " + open.back()->name + " is not closed by END_" +
                                                open.back()->kind + " before END");
        return root;
      }
      if (key == "END_OBJECT" || key == "END_GROUP") {
        const std::string kind = key.substr(4);
        // END_OBJECT may repeat the name (`= TABLE`), or close the innermost block without one.
        skip_blanks_on_line();
        std::string closes;
        if (!at_end() && text_[pos_] == '=') {
          ++pos_;
          closes = rest_of_line_word();
        }
        if (open.size() < 2 || open.back()->kind != kind)
          throw error_at(line, key + (closes.empty() ? "" : " = " + closes) + " closes no open " + kind);
        if (!closes.empty() && closes != open.back()->name)
          throw error_at(line, key + " = " + closes + " closes " + kind + " " + open.back()->name + " (opened on line " +
                                   std::to_string(open.back()->line) + ")");
        open.pop_back();
        continue;
      }
      skip_blanks();
      if (at_end() || text_[pos_] != '=') throw error_at(line, "'" + key + "' has no '= value'");
      ++pos_;
      skip_blanks();
      if (key == "OBJECT" || key == "GROUP") {
        Pds3Object child;
        child.kind = key;
        child.line = line;
        child.name = word();
        if (child.name.empty()) throw error_at(line, key + " without a name");
        open.back()->objects.push_back(std::move(child));
        open.push_back(&open.back()->objects.back());
        continue;
      }
      open.back()->keys.emplace_back(key, value(line));
    }
  }

 private:
  bool at_end() const { return pos_ >= text_.size(); }
  SceneError error(const std::string& what) const { return error_at(line_, what); }
  SceneError error_at(std::size_t line, const std::string& what) const {
    return SceneError(name_ + ":" + std::to_string(line) + ": " + what);
  }

  void advance() {
    if (text_[pos_] == '\n') ++line_;
    ++pos_;
  }
  // Blanks, line ends (CR LF or LF) and /* comments */.
  void skip_blanks() {
    while (!at_end()) {
      const char c = text_[pos_];
      if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\0') {
        advance();
      } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
        const std::size_t line = line_;
        pos_ += 2;
        while (!at_end() && !(text_[pos_] == '*' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/')) advance();
        if (at_end()) throw error_at(line, "a /* comment */ is not closed");
        pos_ += 2;
      } else {
        return;
      }
    }
  }
  void skip_blanks_on_line() {
    while (!at_end() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r')) ++pos_;
  }
  // A keyword, name or bare value: letters, digits, _ ^ : . + - (a namespace, a pointer, a date).
  std::string word() {
    std::string out;
    while (!at_end()) {
      const char c = text_[pos_];
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '^' || c == ':' || c == '.' || c == '+' ||
          c == '-')
        out += c, ++pos_;
      else
        break;
    }
    return out;
  }
  // What follows `END_OBJECT =` on its line (a name, or nothing).
  std::string rest_of_line_word() {
    skip_blanks_on_line();
    if (at_end() || text_[pos_] == '\n') return "";
    return word();
  }
  // Up to the closing `close`, quotes inside kept whole; line breaks kept.
  std::string until(char close, std::size_t line) {
    std::string out;
    while (!at_end() && text_[pos_] != close) {
      if (text_[pos_] == '"') {
        out += text_[pos_];
        advance();
        while (!at_end() && text_[pos_] != '"') out += text_[pos_], advance();
        if (at_end()) break;
      }
      if (text_[pos_] != '\r') out += text_[pos_];
      advance();
    }
    if (at_end()) throw error_at(line, std::string("a value opened on this line has no closing '") + close + "'");
    advance();
    return out;
  }

  Pds3Value value(std::size_t line) {
    Pds3Value v;
    v.line = line;
    if (at_end()) throw error_at(line, "a keyword without a value at the end of the label");
    const char c = text_[pos_];
    if (c == '"') {  // free text, over as many lines as it takes
      advance();
      v.text = until('"', line);
      v.quoted = true;
    } else if (c == '\'') {  // a symbol
      advance();
      v.text = until('\'', line);
    } else if (c == '(' || c == '{') {  // a sequence or a set, kept whole
      advance();
      const std::string inside = until(c == '(' ? ')' : '}', line);
      v.text = std::string(1, c);
      for (const char k : inside)  // blanks and line breaks as one space: "(3, 4, 5)"
        if (k == ' ' || k == '\t' || k == '\n') {
          if (v.text.back() != ' ' && v.text.back() != c) v.text += ' ';
        } else {
          if (v.text.back() == ' ' && (k == ',' || k == ')' || k == '}')) v.text.pop_back();
          v.text += k;
        }
      if (v.text.back() == ' ') v.text.pop_back();
      v.text += c == '(' ? ')' : '}';
    } else {
      // A number, a date, an unquoted symbol — to the end of its line, a <unit> split off.
      // (A /* comment */ after it on its line is the comment's, left for skip_blanks.)
      std::string rest;
      while (!at_end() && text_[pos_] != '\n' &&
             !(text_[pos_] == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*'))
        rest += text_[pos_++];
      while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t' || rest.back() == '\r')) rest.pop_back();
      if (const auto open = rest.find('<'); open != std::string::npos) {
        const auto close = rest.find('>', open);
        if (close == std::string::npos) throw error_at(line, "a unit '<' without its '>'");
        v.unit = rest.substr(open + 1, close - open - 1);
        rest = rest.substr(0, open);
        while (!rest.empty() && rest.back() == ' ') rest.pop_back();
      }
      if (rest.empty()) throw error_at(line, "a keyword without a value");
      v.text = rest;
    }
    return v;
  }

  const std::string& text_;
  std::string name_;
  std::size_t pos_ = 0, line_ = 1;
};

}  // namespace

Pds3Object parse_pds3_label(const std::string& text, const std::string& name) { return Reader(text, name).label(); }

std::string pds3_upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

Pds3Pointer pds3_pointer(const Pds3Object& label, const std::string& key, const std::filesystem::path& file) {
  const Pds3Value* pointer = label.find(key);
  const std::string where = file.string() + ":" + std::to_string(pointer ? pointer->line : label.line) + ": ";
  if (!pointer) throw SceneError(where + "the label has no " + key + " pointer");
  Pds3Pointer out;
  std::string name = pointer->text;
  if (!name.empty() && name.front() == '(') {  // ("NAME", start record)
    const auto open = name.find('"'), close = name.find('"', open + 1);
    if (open == std::string::npos || close == std::string::npos)
      throw SceneError(where + key + " = " + pointer->text + " names no file");
    const std::string start = name.substr(close + 1);
    const auto digit = start.find_first_of("0123456789");
    if (digit == std::string::npos) throw SceneError(where + key + " = " + pointer->text + " has no start record");
    if (start.find("<BYTES>") != std::string::npos)
      throw SceneError(where + key + " = " + pointer->text + ": an offset in bytes is not read (records are)");
    out.record = std::stoul(start.substr(digit));
    if (out.record < 1) throw SceneError(where + key + " = " + pointer->text + ": records count from 1");
    name = name.substr(open + 1, close - open - 1);
  } else if (!pointer->quoted) {
    throw SceneError(where + key + " = " + pointer->text +
                     ": an object inside the label's own file (an attached label) is not read; noether reads "
                     "detached labels (.lbl beside the .tab)");
  }
  const std::filesystem::path folder = file.parent_path();
  std::error_code ec;
  if (std::filesystem::exists(folder / name, ec)) {
    out.file = folder / name;
    return out;
  }
  for (const auto& entry : std::filesystem::directory_iterator(folder.empty() ? "." : folder, ec))
    if (pds3_upper(entry.path().filename().string()) == pds3_upper(name)) {
      out.file = entry.path();
      return out;
    }
  throw SceneError(where + "its " + key.substr(1) + " '" + name + "' is not beside it (looked in " +
                   (folder.empty() ? std::string(".") : folder.string()) + ", any case)");
}

Pds3Object read_pds3_label(const std::filesystem::path& file) {
  constexpr std::uintmax_t kMaxBytes = std::uintmax_t{1} << 24;  // labels are kilobytes
  return parse_pds3_label(read_pds3_file(file, kMaxBytes), file.string());
}

std::string read_pds3_file(const std::filesystem::path& file, std::uintmax_t max_bytes) {
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw SceneError(file.string() + ": not a regular file");
  if (const auto bytes = std::filesystem::file_size(file, ec); !ec && bytes > max_bytes)
    throw SceneError(file.string() + ": " + std::to_string(bytes) + " bytes; noether reads at most " +
                     std::to_string(max_bytes) + " of it");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SceneError(file.string() + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t pds3_count(const Pds3Object& o, const std::string& key, const std::string& file) {
  const Pds3Value* v = o.find(key);
  if (!v) throw SceneError(file + ":" + std::to_string(o.line) + ": " + o.name + " has no " + key);
  char* end = nullptr;
  const long n = std::strtol(v->text.c_str(), &end, 10);
  if (end == v->text.c_str() || *end != '\0' || n <= 0 || n > (1L << 30))
    throw SceneError(file + ":" + std::to_string(v->line) + ": " + key + " = " + v->text + " is not a count");
  return static_cast<std::size_t>(n);
}

std::filesystem::path pds3_label_of(const std::filesystem::path& file) {
  const std::string ext = pds3_upper(file.extension().string());
  if (ext == ".LBL") return file;
  std::error_code ec;
  for (const char* label : {".lbl", ".LBL"})
    if (const auto p = std::filesystem::path(file).replace_extension(label); std::filesystem::exists(p, ec)) return p;
  return {};
}

}  // namespace noether
