// Replays the case loader's fuzz corpus and every crashing input it found (tests/fuzz/, scripts/ci/fuzz.sh):
// each loads to a case or is refused with an exception; a crash, a hang or (in the sanitized build,
// scripts/ci/sanitize.sh) a sanitizer report fails the suite.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "tests/fuzz/case_input.hpp"

namespace fs = std::filesystem;

TEST(FuzzCorpus, EveryInputLoadsOrIsRefused) {
  const fs::path root = fs::path(ISPH_SOURCE_DIR) / "tests" / "fuzz";
  const fs::path dir = fs::temp_directory_path() / ("isph_fuzz_replay_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  int inputs = 0;
  for (const char* folder : {"corpus", "crashes"}) {
    if (!fs::is_directory(root / folder)) continue;
    for (const auto& entry : fs::directory_iterator(root / folder)) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string input{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      SCOPED_TRACE(entry.path().string());
      fuzz::load_case_input(input, dir);
      ++inputs;
    }
  }
  fs::remove_all(dir);
  EXPECT_GE(inputs, 15);  // at least the seeds: the bundled cases
}

namespace {

// The kind of a refusal's reason (docs/RELIABILITY.md's table of bad inputs), or "" for none known.
std::string kind_of(const std::string& reason) {
  const std::pair<const char*, const char*> kinds[] = {
      {"parse error", "TOML syntax"},
      {"not UTF-8", "not UTF-8 text"},
      {"unknown key", "unknown key"},
      {"missing required key", "missing key"},
      {"expected ", "wrong type or length"},
      {"must be one of", "not one of the choices"},
      {"is not available with", "choice not offered with another key's"},
      {"only for", "key not for this element"},
      {"not for kind", "key not for this element"},
      {"only in 3D", "key not for this element"},
      {"only used in 2D", "key not for this element"},
      {"is only for", "key not for this element"},
      {"shape, but dimension", "2D shape in 3D or the reverse"},
      {"must differ", "rule across keys"},
      {"give ", "rule across keys"},
      {"must be > min", "rule across keys"},
      {"must be > surface_threshold", "rule across keys"},
      {"must match", "malformed name"},
      {"must be ", "out of range"},
      {"must not be", "out of range"},
      {"hi must be", "out of range"},
      {"no material named", "reference to a missing element"},
      {"no body named", "reference to a missing element"},
      {"a force probe needs", "force probe on a fluid body"},
      {"duplicate name", "duplicate name"},
      {"has model", "material of the wrong model"},
      {"stages", "stages and bodies disagree"},
      {"probes need", "stages and bodies disagree"},
      {"nothing to run", "stages and bodies disagree"},
      {"cannot open", "motion file"},
      {"line ", "motion file"},
      {"needs at least two rows", "motion file"},
      {"before end_time", "motion file"},
      {"has no clamps", "motion of a structure without clamps"},
      {"is a table", "override syntax"},
      {"not a table or an array", "override syntax"},
      {"expected key=value", "override syntax"},
      {"no element with index", "override syntax"},
  };
  for (const auto& [pattern, kind] : kinds)
    if (reason.find(pattern) != std::string::npos) return kind;
  return "";
}

}  // namespace

// Every refusal names the case file (or the override) and the key, and gives a reason of a known kind;
// the counts per kind, over the corpus, are printed for docs/RELIABILITY.md.
TEST(FuzzCorpus, EveryRefusalNamesTheFileTheKeyAndTheReason) {
  const fs::path root = fs::path(ISPH_SOURCE_DIR) / "tests" / "fuzz";
  const fs::path dir = fs::temp_directory_path() / ("isph_fuzz_kinds_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string file = (dir / "case.toml").string();
  std::map<std::string, int> inputs_of_kind, problems_of_kind;
  int loaded = 0, refused = 0;
  for (const char* folder : {"corpus", "crashes"}) {
    if (!fs::is_directory(root / folder)) continue;
    for (const auto& entry : fs::directory_iterator(root / folder)) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string input{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      const std::vector<std::string> problems = fuzz::case_input_problems(input, dir);
      if (problems.empty()) {
        ++loaded;
        continue;
      }
      ++refused;
      std::map<std::string, bool> kinds;
      for (const std::string& p : problems) {
        const bool named = p.rfind(file + ": ", 0) == 0 || p.rfind("--set ", 0) == 0;
        EXPECT_TRUE(named) << entry.path() << ": a problem that names neither the file nor the override: " << p;
        const std::string kind = kind_of(p);
        EXPECT_FALSE(kind.empty()) << entry.path() << ": a reason of no known kind: " << p;
        ++problems_of_kind[kind];
        kinds[kind] = true;
      }
      for (const auto& [kind, _] : kinds) ++inputs_of_kind[kind];
    }
  }
  fs::remove_all(dir);
  std::printf(
      "corpus: %d inputs loaded, %d refused\n| kind of problem | refused inputs with it | problems "
      "|\n|---|---:|---:|\n",
      loaded, refused);
  for (const auto& [kind, count] : inputs_of_kind)
    std::printf("| %s | %d | %d |\n", kind.c_str(), count, problems_of_kind[kind]);
  EXPECT_GT(refused, 0);
}
