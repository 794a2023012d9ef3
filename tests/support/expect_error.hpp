#pragma once
// The project error a call throws, for tests of bad input (docs/reliability.md): the test then
// checks its kind, exit code, file, line and field.
#include <functional>

#include "config/error.hpp"

namespace rangecal::test {

/// The rangecal::Error `f` throws; a test failure (and an empty usage error) when it throws nothing
/// or another exception.
Error expect_error(const std::function<void()>& f);

}  // namespace rangecal::test
