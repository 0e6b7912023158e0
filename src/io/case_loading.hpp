#pragma once
// What the case loader's parts share (io/case_loader.cpp reads, io/case_checks.cpp checks across the
// lists, io/case_overrides.cpp applies --set): the problems found so far, and text helpers.
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <toml.hpp>
#include <vector>

#include "io/case.hpp"

namespace isph::case_loading {

// Every problem found is recorded here, and reading goes on.
struct Context {
  explicit Context(std::string file_name) : file(std::move(file_name)) {}

  std::string file;
  int dimension = 2;  // read first; vectors have this many components
  std::vector<std::string> problems;
  std::set<std::string> unknown_model;  // materials whose model was refused: their bodies are not judged

  void problem(const std::string& key, const std::string& reason) {
    problems.push_back(file + ": " + key + ": " + reason);
  }
};

inline std::string join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string text;
  for (std::size_t i = 0; i < parts.size(); ++i) text += (i ? separator : "") + parts[i];
  return text;
}

inline std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

inline std::vector<std::string> split(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::istringstream in(s);
  for (std::string part; std::getline(in, part, separator);) parts.push_back(part);
  if (!s.empty() && s.back() == separator) parts.emplace_back();
  return parts;
}

inline std::string index_path(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

// What a TOML value is, for messages ("an integer", "a table", ...).
inline std::string describe(const toml::value& v) {
  switch (v.type()) {
    case toml::value_t::boolean:
      return "a boolean";
    case toml::value_t::integer:
      return "an integer";
    case toml::value_t::floating:
      return "a float";
    case toml::value_t::string:
      return "a string";
    case toml::value_t::array:
      return "an array";
    case toml::value_t::table:
      return "a table";
    case toml::value_t::empty:
      return "nothing";
    default:
      return "a date or time";
  }
}

// The checks across the lists (names unique, references known, materials fit their bodies, the stages the
// bodies need), with the motion files and the meshes' sizes read (io/case_checks.cpp).
void check_lists(CaseSpec& c, Context& ctx);

// The offset of the first byte of `text` that does not belong to a well-formed UTF-8 sequence, if any.
std::optional<std::size_t> first_invalid_utf8(std::string_view text);
// Sets "dotted.key=value" in `doc` (io/case_overrides.cpp); returns why it could not, if so.
std::optional<std::string> apply_override(toml::value& doc, const std::string& text);

}  // namespace isph::case_loading
