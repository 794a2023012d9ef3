#include "support/expect_error.hpp"

#include <gtest/gtest.h>

#include <exception>

namespace rangecal::test {

Error expect_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a rangecal::Error: " << e.what();
    return Error(ErrorKind::usage, "", 0, "", "");
  }
  ADD_FAILURE() << "no rangecal::Error thrown";
  return Error(ErrorKind::usage, "", 0, "", "");
}

}  // namespace rangecal::test
