// Replays the case loader's fuzz corpus and every crashing input it found (tests/fuzz/, scripts/fuzz.sh):
// each loads to a case or is refused with an exception; a crash, a hang or (in the sanitized build,
// scripts/sanitize.sh) a sanitizer report fails the suite.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

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
