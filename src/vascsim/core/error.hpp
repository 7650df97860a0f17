#pragma once
// Errors that reach the user. The CLI turns an Error into one clear line and exit code 2; anything
// else escaping is a bug.

#include <stdexcept>
#include <string>

namespace vascsim {

/// Bad input (scene file, key, value, geometry that cannot be discretised). The message is complete
/// on its own: it names the file, the key and what is allowed.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A numerical failure the user must know about (ill-conditioned node, solver divergence).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace vascsim
