#pragma once
// What the regression tests share: running the `isph` command and reading its output files.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace regression {

// The source tree and the isph binary of the build; ISPH_TEST_SOURCE_DIR and ISPH_TEST_BINARY replace
// them where the programs were carried elsewhere (bench/gpu_session.sh on a lent GPU machine).
inline std::string from_environment(const char* name, const char* built_with) {
  const char* v = std::getenv(name);
  return v && *v ? v : built_with;
}
inline const std::string kSource = from_environment("ISPH_TEST_SOURCE_DIR", ISPH_SOURCE_DIR);
inline const std::string kCases = kSource + "/cases/";
inline const std::string kIsph = from_environment("ISPH_TEST_BINARY", ISPH_BINARY);

struct CommandResult {
  int status;
  std::string output;  // stdout and stderr
};

// Runs the isph command. Runs use one thread: ctest runs tests side by side, and OpenMP threads
// on oversubscribed cores slow a run down many times over.
inline CommandResult isph(const std::string& args) {
  const bool run = args.rfind("run ", 0) == 0;
  const std::string cmd = kIsph + " " + args + (run ? " --threads 1" : "") + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (pipe && fgets(buf, sizeof buf, pipe)) out += buf;
  const int rc = pipe ? pclose(pipe) : -1;
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, out};
}

// Every test process writes its runs under a folder of its own, isph_regression_<pid> in the temporary
// folder, so that two suites run at once on one machine (a developer's build and a fresh clone's) cannot
// remove or overwrite each other's outputs. The folder is removed when every test of the process passed,
// and kept, with its path printed, when one failed.
class TestOutputRoot : public ::testing::Environment {
 public:
  static const fs::path& path() {
    static const fs::path root = fs::temp_directory_path() / ("isph_regression_" + std::to_string(::getpid()));
    return root;
  }
  void TearDown() override {
    if (!fs::exists(path())) return;
    if (::testing::UnitTest::GetInstance()->Passed())
      fs::remove_all(path());
    else
      std::cerr << "the runs' outputs are kept in " << path().string() << "\n";
  }
};
inline ::testing::Environment* const kTestOutputRoot = ::testing::AddGlobalTestEnvironment(new TestOutputRoot);

inline fs::path fresh_dir(const std::string& name) {
  const fs::path p = TestOutputRoot::path() / name;
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

// Runs a bundled case on `device` (cpu, cuda or debug) into a fresh folder, without
// snapshots, and returns the folder; the run must complete.
inline fs::path run_on_device(const std::string& device, const std::string& name, const std::string& case_file,
                              const std::string& sets) {
  const fs::path out = fresh_dir(name + "_" + device);
  const auto r = isph("run " + kCases + case_file + " --quiet --out " + out.string() + " --device " + device +
                      " --set output.snapshots=false" + sets);
  EXPECT_EQ(r.status, 0) << device << ": " << r.output;
  return out;
}

// A CSV with a header, as columns by name.
inline std::map<std::string, std::vector<double>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) names.push_back(c);
  std::map<std::string, std::vector<double>> cols;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::size_t k = 0;
    // strtod, not stod: a force that decays to a subnormal (4e-320 N) is a value, not an error
    for (std::string c; std::getline(row, c, ',') && k < names.size(); ++k)
      cols[names[k]].push_back(std::strtod(c.c_str(), nullptr));
  }
  return cols;
}

// A reference curve (t, u) from ../shared/reference, sorted by time (two columns, no header).
inline std::vector<std::pair<double, double>> read_reference(const std::string& path_in_reference) {
  std::ifstream in(std::string(ISPH_REFERENCE_DIR) + "/" + path_in_reference);
  std::vector<std::pair<double, double>> rows;
  for (double t, u; in >> t && in.ignore(1) >> u;) rows.emplace_back(t, u);
  std::sort(rows.begin(), rows.end());
  return rows;
}

// u linearly interpolated at time t from samples (time[k], u[k]) ascending in time.
inline double interpolate(const std::vector<double>& time, const std::vector<double>& u, double t) {
  const auto it = std::upper_bound(time.begin(), time.end(), t);
  if (it == time.begin()) return u.front();
  if (it == time.end()) return u.back();
  const std::size_t k = static_cast<std::size_t>(it - time.begin());
  return u[k - 1] + (u[k] - u[k - 1]) * (t - time[k - 1]) / (time[k] - time[k - 1]);
}

// A reference curve (read_reference) linearly interpolated at time t.
inline double interpolate(const std::vector<std::pair<double, double>>& curve, double t) {
  std::vector<double> time, u;
  for (const auto& [ti, ui] : curve) time.push_back(ti), u.push_back(ui);
  return interpolate(time, u, t);
}

// RMSE of a run's u(t) against the reference points inside the run's time range (as
// scripts/validate/coupled_report.py computes it).
inline double rmse_against(const std::vector<double>& time, const std::vector<double>& u,
                           const std::vector<std::pair<double, double>>& reference) {
  double sum = 0;
  std::size_t count = 0;
  for (const auto& [t, value] : reference)
    if (t >= time.front() && t <= time.back()) {
      const double e = interpolate(time, u, t) - value;
      sum += e * e;
      ++count;
    }
  return count ? std::sqrt(sum / count) : std::numeric_limits<double>::quiet_NaN();
}

// The mean of a probe column over the rows at or after `from` (and its standard deviation).
inline double mean_over(const std::vector<double>& t, const std::vector<double>& v, double from,
                        double* stddev = nullptr) {
  double s = 0, s2 = 0;
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= from) s += v[k], s2 += v[k] * v[k], ++n;
  const double m = s / n;
  if (stddev) *stddev = std::sqrt(std::max(0.0, s2 / n - m * m));
  return m;
}

inline std::string read_file(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The number after the first "key": in a JSON text (NaN if the key is absent).
inline double json_number(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  return std::stod(json.substr(at + key.size() + 3));
}

}  // namespace regression

using namespace regression;  // NOLINT: the tests use these names plainly
