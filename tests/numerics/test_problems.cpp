// numerics::Problems, which every option struct validates into (db::Problems is the same type).
#include <gtest/gtest.h>

#include <string>

#include "numerics/problems.hpp"

namespace yarnfit::numerics {
namespace {

TEST(Problems, OptionProblemsRenderAsFieldAndMessageAndJoinOnOneLine) {
  Problems p;
  EXPECT_TRUE(p.empty());
  EXPECT_EQ(p.one_line(), "");
  p.add_field("particles", "must be at least 2 (got 1)");
  p.add("tile.pyp", 3, "vertices", "expected a number");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.items()[0].to_string(), "particles: must be at least 2 (got 1)");
  EXPECT_EQ(p.to_string(), "particles: must be at least 2 (got 1)\ntile.pyp:3: vertices: expected a number\n");
  EXPECT_EQ(p.one_line(), "particles: must be at least 2 (got 1); tile.pyp:3: vertices: expected a number");
}

TEST(Problems, AppendWithAPrefixNamesTheNestedField) {
  Problems inner;
  inner.add_field("shrink", "must be in (0, 1)");
  Problems outer;
  outer.add_field("max_rounds", "must be at least 1 (got 0)");
  outer.append(inner, "fallback.");
  outer.append(inner);
  ASSERT_EQ(outer.size(), 3u);
  EXPECT_EQ(outer.items()[1].field, "fallback.shrink");
  EXPECT_EQ(outer.items()[1].message, "must be in (0, 1)");
  EXPECT_EQ(outer.items()[2].field, "shrink");
}

}  // namespace
}  // namespace yarnfit::numerics
