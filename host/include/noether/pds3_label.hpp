#pragma once
// A PDS3 label (the Planetary Data System's Object Description Language, PDS3 Standards Reference
// ch. 12) as archived: `KEYWORD = value` statements, values quoted over several lines, symbols,
// numbers with units in `<...>`, sequences and sets in (...) and {...}, /* comments */, nested
// OBJECT/GROUP blocks closed by END_OBJECT/END_GROUP, the END statement; CRLF line ends and space
// padding to fixed-length records are read as they are. Errors name the file and line.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace noether {

struct Pds3Value {
  std::string text;  // the value as written: a quoted string's content (its line breaks kept), a
                     // symbol's or number's characters, a sequence with its brackets
  std::string unit;  // what `<...>` after a number says ("" when nothing)
  std::size_t line = 0;
  bool quoted = false;  // "..." (free text, or a name such as a file's)
};

struct Pds3Object {
  std::string kind;  // "OBJECT" or "GROUP" ("" for the label itself)
  std::string name;  // TABLE, COLUMN, … ("" for the label itself)
  std::size_t line = 0;
  std::vector<std::pair<std::string, Pds3Value>> keys;  // in the label's order (^POINTERs with their ^)
  std::vector<Pds3Object> objects;                      // nested OBJECTs and GROUPs, in order

  // The value of `key` (exact, as written upper case), or null.
  const Pds3Value* find(const std::string& key) const;
  // The first nested object named `name` (TABLE, …), or null.
  const Pds3Object* object(const std::string& name) const;
};

// Where a detached label's pointer (^TABLE, ^VERTEX_TABLE, …) points: `"NAME.TAB"` or
// `("NAME.TAB", record)`, the file beside the label with its name's case as the disk has it
// (archives print names upper case), and the 1-based record its object starts at. Throws
// SceneError (no such pointer, a pointer into the label's own file, a file not there).
struct Pds3Pointer {
  std::filesystem::path file;
  std::size_t record = 1;
};
Pds3Pointer pds3_pointer(const Pds3Object& label, const std::string& key, const std::filesystem::path& label_file);

// What the readers of a label's products share: names compared upper case, as PDS3 writes them;
// a positive count of an object (ROWS, BYTES, START_BYTE, …), SceneError naming the file and line
// when it is absent or not one; a product's file read whole, a regular file of at most
// `max_bytes`; and the label of a product given by either file (`file` when it is a .lbl, else the
// .lbl or .LBL of its name beside it, else "").
std::string pds3_upper(std::string text);
std::size_t pds3_count(const Pds3Object& object, const std::string& key, const std::string& file);
std::string read_pds3_file(const std::filesystem::path& file, std::uintmax_t max_bytes);
std::filesystem::path pds3_label_of(const std::filesystem::path& file);

// The label of `file`: the root object, `file` named in each error. Throws SceneError.
Pds3Object read_pds3_label(const std::filesystem::path& file);
// The same from text (`name` in errors).
Pds3Object parse_pds3_label(const std::string& text, const std::string& name);

}  // namespace noether
