#pragma once
// Scene text as a Params tree (internal to libnoether; scene_yaml.cpp): the YAML read with
// every node's "file:line", and the --set overrides applied to it.
#include <noether/params.hpp>

#include <string>

namespace noether {

// The YAML document `text` (read from `file`, for messages) as a tree; SceneError on malformed
// YAML or a document that expands beyond the limits against alias bombs.
Params parse_yaml(const std::string& text, const std::string& file);
// "--set a.b.c=value": edits the tree in place (SceneError naming the key when it cannot).
void apply_override(Params& root, const std::string& assignment);

}  // namespace noether
