#pragma once
// Reads and validates a case file (TOML). Every problem found is collected, so that `isph check`
// can report all of them at once; each names the file, the key and the reason.
#include <stdexcept>
#include <string>
#include <vector>

#include "io/case.hpp"

namespace isph {

class CaseError : public std::runtime_error {
 public:
  explicit CaseError(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

// Parses `path`, applies `overrides` ("dotted.key=value", value parsed as a TOML value, else taken
// as a string), validates, fills defaults and returns the case. Throws CaseError listing every
// problem ("<file>: <key>: <reason>").
CaseSpec load_case(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace isph
