// yarnfit's one error type (numerics/util/error.hpp): the category is what the user can do, it
// survives a layer that adds where the error happened, and the sources throw the category the
// architecture documents (docs/architecture.md, "Errors").
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "numerics/util/error.hpp"
#include "numerics/util/whole_file.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit {
namespace {

TEST(Error, OnlyInputAndConflictAreTheUsersToMend) {
  EXPECT_TRUE(Error(ErrorCategory::input, "x").users_to_mend());
  EXPECT_TRUE(Error(ErrorCategory::conflict, "x").users_to_mend());
  EXPECT_FALSE(Error(ErrorCategory::io, "x").users_to_mend());
  EXPECT_FALSE(Error(ErrorCategory::solve, "x").users_to_mend());
  EXPECT_FALSE(Error(ErrorCategory::system, "x").users_to_mend());
}

TEST(Error, ContextIsAddedAndTheCategoryKept) {
  const Error inner(ErrorCategory::conflict, "out/fabric.yaml: exists");
  const Error outer = with_context("synth: ", inner);
  EXPECT_EQ(outer.category(), ErrorCategory::conflict);
  EXPECT_STREQ(outer.what(), "synth: out/fabric.yaml: exists");
  // Every catch of the standard exceptions the code had before still sees it.
  try {
    throw outer;
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "synth: out/fabric.yaml: exists");
  }
}

TEST(Error, AFileThatCannotBeWrittenIsAnIoError) {
  const std::filesystem::path missing = std::filesystem::temp_directory_path() / "yarnfit_no_such_folder" / "x.json";
  EXPECT_ERROR(numerics::write_file_whole(missing, "{}\n"), ErrorCategory::io);
}

}  // namespace
}  // namespace yarnfit
