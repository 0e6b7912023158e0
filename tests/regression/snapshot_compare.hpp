#pragma once
// Snapshots compared value by value (the restart tests), apart from run_support.hpp so that the tests
// that name regression::isph plainly do not see namespace isph.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/output.hpp"

namespace regression {

// Every value of every field of two snapshots is the same double.
inline void expect_same_bits(const fs::path& a, const fs::path& b) {
  const isph::SnapshotData x = isph::read_snapshot(a.string()), y = isph::read_snapshot(b.string());
  EXPECT_EQ(x.time, y.time);
  ASSERT_EQ(x.fields.size(), y.fields.size());
  for (const auto& [name, field] : x.fields) {
    const auto& other = y.field(name).data;
    ASSERT_EQ(field.data.size(), other.size()) << name;
    std::size_t differ = 0;
    for (std::size_t k = 0; k < other.size(); ++k) differ += field.data[k] != other[k];
    EXPECT_EQ(differ, 0u) << name << ": " << a << " against " << b;
  }
}

}  // namespace regression
