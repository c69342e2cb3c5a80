#pragma once
// Bad input from the user: the tool prints one line on stderr naming the problem and exits with 2.

#include <stdexcept>

namespace gvcli {

struct usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace gvcli
