#pragma once
/// One row of the forming validation table in docs/heat-and-forming.md: a physics test prints what it checks, against
/// what reference, with which tolerance, what it measured and whether that holds, on one line that docs/figures.sh
/// collects. The table's figures so come from the tests that enforce them, never typed by hand.

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace masse::test
{
/// Prints `validation|check|reference|tolerance|measured|holds or fails|Suite.Test`; a '|' inside a field is not
/// allowed (it would split the table's cell), so the fields are plain prose.
inline void printValidationRow(const std::string& check, const std::string& reference, const std::string& tolerance,
                               const std::string& measured, bool holds)
{
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = test ? std::string(test->test_suite_name()) + "." + test->name() : "";
    std::printf("validation|%s|%s|%s|%s|%s|%s\n", check.c_str(), reference.c_str(), tolerance.c_str(), measured.c_str(),
                holds ? "holds" : "fails", name.c_str());
    std::fflush(stdout);
}
} // namespace masse::test
