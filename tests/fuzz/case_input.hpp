#pragma once
// One input of the case loader's fuzz target (tests/fuzz/fuzz_case_loader.cpp), also replayed by the unit
// test FuzzCorpus.EveryInputLoadsOrIsRefused: a case file's TOML text, then, after a line "--set", one
// override per line, then, after a line "--csv", the text of a file "motion.csv" beside the case, which
// a case may name as a body's motion history.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/case_loader.hpp"

namespace fuzz {

// Loads the input from files in `dir` (its case file is dir / "case.toml"): returns the problems of a
// refusal (CaseError), none when it loads, and a single "exception: ..." for any other std::exception;
// anything else escapes.
inline std::vector<std::string> case_input_problems(std::string_view input, const std::filesystem::path& dir) {
  std::string toml(input), overrides, csv;
  if (const auto at = toml.find("\n--csv\n"); at != std::string::npos) {
    csv = toml.substr(at + 7);
    toml.resize(at);
  }
  if (const auto at = toml.find("\n--set\n"); at != std::string::npos) {
    overrides = toml.substr(at + 7);
    toml.resize(at);
  }
  std::ofstream(dir / "case.toml", std::ios::binary) << toml;
  std::ofstream(dir / "motion.csv", std::ios::binary) << csv;
  std::vector<std::string> sets;
  std::istringstream lines(overrides);
  for (std::string line; std::getline(lines, line);) sets.push_back(line);
  try {
    (void)isph::load_case((dir / "case.toml").string(), sets);
  } catch (const isph::CaseError& e) {
    return e.problems();
  } catch (const std::exception& e) {
    return {std::string("exception: ") + e.what()};
  }
  return {};
}

inline void load_case_input(std::string_view input, const std::filesystem::path& dir) {
  (void)case_input_problems(input, dir);
}

}  // namespace fuzz
