#pragma once
// EXPECT_ERROR(statement, category): the statement throws yarnfit's Error of that category
// (numerics/util/error.hpp), not another category and not another exception.

#include <gtest/gtest.h>

#include <exception>
#include <string>

#include "numerics/util/error.hpp"

namespace yarnfit::testing {

template <class Statement>
::testing::AssertionResult throws_error(ErrorCategory category, Statement&& statement) {
  try {
    statement();
  } catch (const yarnfit::Error& e) {
    if (e.category() == category) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "an Error of category " << static_cast<int>(e.category()) << ", not "
                                         << static_cast<int>(category) << ": " << e.what();
  } catch (const std::exception& e) {
    return ::testing::AssertionFailure() << "another exception: " << e.what();
  }
  return ::testing::AssertionFailure() << "nothing thrown";
}

}  // namespace yarnfit::testing

#define EXPECT_ERROR(statement, category) \
  EXPECT_TRUE(::yarnfit::testing::throws_error(category, [&] { statement; })) << #statement
