#pragma once
// The settings of a case file, each key declared once (docs/CASES.md, "Settings"): its section, name,
// type, unit, allowed range or choices, default and a line of documentation, with its place in
// CaseSpec. The loader reads and checks the settings from this table, the resolved case is written
// from it, and docs/CASES.md's key tables are generated from it (`isph keys`). The lists (materials,
// bodies, loads, probes) and [periodic], whose keys depend on each element's type, keep their own
// readers (case_loader.cpp); the cross-key rules of a section (a preconditioner that its backend must
// offer, for one) are checked there after the section's keys.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "io/case.hpp"

namespace isph {

using KeyValue = std::variant<bool, std::int64_t, double, std::string, std::array<double, 3>>;

enum class KeyType { boolean, integer, number, vector, text, choice };

// The allowed interval of a number or an integer; infinite ends are open.
struct KeyBounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool admits(double x) const { return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi); }
  // "> 0", ">= 0 and < 1", "in 0..100" (integers): for messages and the docs.
  std::string text(bool integer) const;
};

struct CaseKey {
  std::string section;  // "" (top level), "fluid", "fluid.ppe", ...
  std::string name;
  KeyType type = KeyType::number;
  std::string unit;                  // SI, for the docs; empty when dimensionless
  KeyBounds bounds;                  // integer, number
  std::vector<std::string> choices;  // choice
  bool required = false;
  std::string default_note;  // the docs' default when it is not the default CaseSpec's value
  std::string doc;
  std::function<KeyValue(const CaseSpec&)> get;
  std::function<void(CaseSpec&, const KeyValue&)> set;

  std::string path() const { return section.empty() ? name : section + "." + name; }
};

// Every settings key, in the order of the resolved case and the docs.
const std::vector<CaseKey>& case_keys();
// The settings sections in that order, the top level ("") first.
const std::vector<std::string>& case_sections();

// TOML text of a value (vectors with `dimension` components).
std::string toml_value(const KeyValue& value, int dimension);
std::string toml_float(double x);               // with ".0" where it would read as an integer
std::string toml_string(const std::string& s);  // a TOML basic string
// `must be one of "a", "b"`: the allowed names of a choice, for error messages.
std::string one_of(const std::vector<std::string>& allowed);
std::string shortest_number(double x);  // the shortest text that reads back as the same double

// The markdown table of a section's keys (docs/CASES.md).
std::string key_reference(const std::string& section);
// `document` with every block between "<!-- keys SECTION -->" and "<!-- end keys -->" regenerated.
// Throws std::runtime_error naming a section without a block or an unknown one.
std::string with_key_reference(const std::string& document);

}  // namespace isph
