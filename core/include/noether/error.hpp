#pragma once
// Errors: every failure noether reports derives from noether::Error and carries a message a
// user can act on (what went wrong, where, and what to change).
//
// Each class has its destructor defined in libnoether (its key function), so that its vtable
// lives there and not in a plugin: an exception thrown by a plugin stays valid after the
// plugin library is unloaded during stack unwinding.

#include <stdexcept>
#include <string>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

namespace noether {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  ~Error() override;
};

// A scene that cannot be run: malformed YAML, a missing or unknown key, impossible physics.
// The message starts with "file:line:" when the place is known.
class SceneError : public Error {
 public:
  using Error::Error;
  ~SceneError() override;
};

// A plugin that cannot be found, loaded or used.
class PluginError : public Error {
 public:
  using Error::Error;
  ~PluginError() override;
};

// An integrator that cannot continue (a Newton solve that fails, a step too large for the
// spin, a solver error). `t_reached` is the last time at which the state was valid.
class IntegrationError : public Error {
 public:
  IntegrationError(const std::string& what, double t_reached)
      : Error(what), t_reached_(t_reached) {}
  ~IntegrationError() override;
  double t_reached() const { return t_reached_; }

 private:
  double t_reached_;
};

// Output files that cannot be written.
class OutputError : public Error {
 public:
  using Error::Error;
  ~OutputError() override;
};

}  // namespace noether

#pragma GCC visibility pop
