#include "fabrics_db/csv/csv_table.hpp"

#include <gtest/gtest.h>

namespace yarnfit::db {
namespace {

TEST(CsvTable, KeepsSourceLinesAndSkipsCommentsAndBlanks) {
  Problems p;
  const auto t = parse_csv("# meta\n\na,b\r\n1,2\n\n3,4\n", "x.csv", CsvOptions{}, p);
  ASSERT_TRUE(t) << p.to_string();
  EXPECT_EQ(t->header_line, 3);
  EXPECT_EQ(t->header, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(t->rows.size(), 2u);
  EXPECT_EQ(t->rows[0].line, 4);
  EXPECT_EQ(t->rows[1].line, 6);
  EXPECT_EQ(t->column("b"), 1);
  EXPECT_FALSE(t->column("c"));
}

TEST(CsvTable, QuotedFieldsAndOtherDelimiters) {
  EXPECT_EQ(split_csv_line(" a , \"b, c\" ,\"say \"\"hi\"\"\"", ','),
            (std::vector<std::string>{"a", "b, c", "say \"hi\""}));
  EXPECT_EQ(split_csv_line("1;2;;4", ';'), (std::vector<std::string>{"1", "2", "", "4"}));
}

// Found by fuzz_uniform_targets and fuzz_tensile_import (tests/fuzz_regressions): a quote left
// open after a quoted cell threw std::out_of_range, the first cell's quote end applied to it.
TEST(CsvTable, AQuoteLeftOpenHoldsTheRestOfTheLine) {
  EXPECT_EQ(split_csv_line("\"long text\"x,\"ab", ','), (std::vector<std::string>{"long textx", "ab"}));
  EXPECT_EQ(split_csv_line("\"a, b ", ','), (std::vector<std::string>{"a, b "}));
}

TEST(CsvTable, SkipLinesAndEmptyFile) {
  Problems p;
  const auto t = parse_csv("junk\nmore junk\nx,y\n1,2\n", "f.csv", CsvOptions{',', 2}, p);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->header_line, 3);
  EXPECT_FALSE(parse_csv("\n# only comments\n", "e.csv", CsvOptions{}, p));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p.items()[0].to_string(), "e.csv: header: no header line: the file has no CSV content");
}

TEST(ParseFiniteNumber, AcceptsDecimalsRejectsEverythingElse) {
  std::string why;
  EXPECT_EQ(parse_finite_number(" 1.5e-3 ", why), 1.5e-3);
  EXPECT_EQ(parse_finite_number("+2", why), 2.0);
  EXPECT_EQ(parse_finite_number("-0.25", why), -0.25);
  for (const char* bad : {"", "abc", "1.2.3", "1,5", "nan", "NaN", "inf", "-Infinity", "1e999", "3 N"}) {
    EXPECT_FALSE(parse_finite_number(bad, why)) << bad;
    EXPECT_FALSE(why.empty()) << bad;
  }
  parse_finite_number("nan", why);
  EXPECT_EQ(why, "NaN is not a valid value");
}

TEST(Problem, RendersFileLineFieldMessage) {
  EXPECT_EQ((Problem{"a/b.csv", 7, "force_N", "negative force"}).to_string(),
            "a/b.csv:7: force_N: negative force");
  EXPECT_EQ((Problem{"a/b.csv", 0, "file", "no such file"}).to_string(), "a/b.csv: file: no such file");
}

}  // namespace
}  // namespace yarnfit::db
