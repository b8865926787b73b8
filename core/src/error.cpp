#include <noether/error.hpp>

namespace noether {

// Key functions: the vtables of the error types live in libnoether.
Error::~Error() = default;
SceneError::~SceneError() = default;
PluginError::~PluginError() = default;
IntegrationError::~IntegrationError() = default;
OutputError::~OutputError() = default;

}  // namespace noether
