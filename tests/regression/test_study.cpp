// The study runner (scripts/validate/study.py) on cases/studies/smoke.toml: two resolutions of the oscillating
// plate, a few seconds. Checks the table and the charts it writes, not the physics (the structure tests
// do that). Skipped without Debian's python with matplotlib, numpy and h5py.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "run_support.hpp"

namespace {

const std::string kPython = "/usr/bin/python3";

// The comma-separated fields of a CSV line (the study's cells hold no commas).
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) out.push_back(c);
  return out;
}

}  // namespace

TEST(Study, SmokeStudyWritesTableAndCharts) {
  if (!fs::exists(kPython) ||
      std::system((kPython + " -c 'import tomllib, matplotlib, numpy, h5py' >/dev/null 2>&1").c_str()) != 0)
    GTEST_SKIP() << kPython << " with tomllib, matplotlib, numpy and h5py is needed";
  const fs::path out = fresh_dir("study");
  fs::create_directories(out);
  const std::string cmd = kPython + " " + kSource + "/scripts/validate/study.py " + kCases +
                          "studies/smoke.toml --out " + out.string() + " --isph " + kIsph + " --threads 1 > " +
                          (out / "study.log").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << read_file(out / "study.log");

  std::stringstream csv(read_file(out / "study.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line)) << "study.csv is empty";
  const auto header = fields(line);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << "no column " << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t status = column("status"), error = column("error"), wall = column("wall_time_s");
  int rows = 0;
  while (std::getline(csv, line)) {
    if (line.empty()) continue;
    ++rows;
    const auto row = fields(line);
    ASSERT_GT(row.size(), std::max({status, error, wall})) << line;
    EXPECT_EQ(row[status], "completed") << line;
    EXPECT_TRUE(std::isfinite(std::stod(row[error]))) << line;
    EXPECT_GT(std::stod(row[wall]), 0.0) << line;
  }
  EXPECT_EQ(rows, 2);
  for (const char* chart : {"pareto.png", "convergence.png"}) {
    ASSERT_TRUE(fs::exists(out / chart)) << chart;
    EXPECT_GT(fs::file_size(out / chart), 1000u) << chart;
  }
  EXPECT_TRUE(fs::exists(out / "study.md"));
}
