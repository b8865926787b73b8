#pragma once
// Workspace: the memory one evaluating thread of a Potential writes — its scratch and its
// records of the run (docs/writing-a-plugin.md, "Models and workspaces"). A Potential is an
// immutable model that any number of threads may share; each thread (each integrator, each
// ensemble sample) evaluates it with a workspace of its own from Potential::make_workspace(),
// as Pinocchio separates its Model from its Data.
#include <noether/error.hpp>

#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class Workspace {
 public:
  virtual ~Workspace();
};

// The workspace a potential made, as its own type: `who` names the potential in the error
// when it was handed another potential's workspace (a programming error, never silent).
template <class Own>
Own& workspace_as(Workspace& workspace, const char* who) {
  if (auto* own = dynamic_cast<Own*>(&workspace)) return *own;
  throw Error(std::string(who) + ": evaluated with a workspace another potential made; "
              "use this potential's make_workspace()");
}
template <class Own>
const Own& workspace_as(const Workspace& workspace, const char* who) {
  return workspace_as<Own>(const_cast<Workspace&>(workspace), who);
}

}  // namespace noether

#pragma GCC visibility pop
