#pragma once
// The case file's schema engine: every key of a case file, a setting ([fluid.ppe] tolerance) or a key of a
// list element ([[bodies]] shape), is one SchemaKey, declared once (case_schema.cpp for the settings,
// list_schema.cpp and list_schema_bodies.cpp for the lists; the builder: schema_declaration.hpp) with its
// name, type, unit, allowed range or choices, default, a line of documentation (the longer prose stands
// below its table in docs/CASES.md), its place in the spec and the elements it is for. From these
// declarations one reader checks and reads the keys (case_loader.cpp), one writer gives the resolved case
// (key_text, entries) and one generator writes docs/CASES.md's tables (`isph keys`).
#include <array>
#include <functional>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "io/case.hpp"

namespace isph {

// The allowed interval of a number or an integer; infinite ends are open.
struct KeyBounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool admits(double x) const { return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi); }
  // "> 0", ">= 0 and < 1", "in 0..100" (integers): for messages and the docs.
  std::string text(bool integer) const;
};

// Where a value key's value lives in its element.
using FieldRef = std::variant<bool*, int*, double*, std::string*, std::array<double, 3>*, std::vector<double>*, Shape*,
                              std::vector<Shape>*, MotionSpec*, InitialVelocitySpec*>;

template <class Item>
struct SchemaKey {
  std::string section;  // a setting's section: "" (top level), "fluid", "fluid.ppe", ...; lists: ""
  std::string name;
  std::string type;                  // the docs' type: "float", "integer", "string", "vector", "shape", ...
  std::string unit;                  // SI, for the docs
  KeyBounds bounds;                  // a number or an integer
  bool direction = false;            // a non-zero vector, stored normalized
  std::vector<std::string> choices;  // a choice key's names (an enum's)
  // The names a dimension offers, where it offers fewer (a shape's type); `check` then says why another is wrong.
  std::function<std::vector<std::string>(int dimension)> choices_in;
  bool discriminator = false;  // a choice the later keys depend on: when it is bad they are not judged
  // For which elements the key is allowed (null: all) and, for one it is not allowed for, why (the
  // message names the element's own value); `for_text` says it in the docs.
  std::function<bool(const Item&, int dimension)> applies;
  std::function<std::string(const Item&, int dimension)> not_for;
  std::string for_text;
  std::function<bool(const Item&)> required;         // null: optional
  std::function<void(Item&, int dimension)> preset;  // sets a default that depends on the keys before it
  std::string default_text;                          // the docs' default when not the default spec's value
  std::string doc;
  // A value key's place; a choice key's name and setter.
  std::function<FieldRef(Item&)> field;
  std::function<std::string(const Item&)> get_name;
  std::function<void(Item&, const std::string&)> set_name;
  // A problem with the value read (given the element and the dimension), or "".
  std::function<std::string(const Item&, int dimension)> check;
  // Whether the resolved case writes it (null: whenever it applies).
  std::function<bool(const Item&)> written;

  std::string path() const { return section.empty() ? name : section + "." + name; }
};

// TOML text.
std::string shortest_number(double x);          // the shortest text that reads back as the same double
std::string toml_float(double x);               // with ".0" where it would read as an integer
std::string toml_string(const std::string& s);  // a TOML basic string
std::string toml_vector(const std::array<double, 3>& v, int dimension);  // its first `dimension` components
// `must be one of "a", "b"`: the allowed names of a choice, for error messages.
std::string one_of(const std::vector<std::string>& allowed);

// The TOML text of the value a field holds (a shape or a motion as an inline table).
std::string value_text(const FieldRef& field, int dimension);

template <class Item>
std::string key_text(const SchemaKey<Item>& key, const Item& item, int dimension) {
  if (key.get_name) return toml_string(key.get_name(item));
  return value_text(key.field(const_cast<Item&>(item)), dimension);  // read only
}

// The `key = value` entries of an element's keys that apply to it and are written, for the resolved case.
template <class Item>
std::vector<std::pair<std::string, std::string>> entries(const Item& item, const std::vector<SchemaKey<Item>>& keys,
                                                         int dimension) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& key : keys) {
    if (key.applies && !key.applies(item, dimension)) continue;
    if (key.written && !key.written(item)) continue;
    out.emplace_back(key.name, key_text(key, item, dimension));
  }
  return out;
}

// The docs' tables (docs/CASES.md): a number as the docs show it (1e-8, not 1e-08), a markdown cell ('|'
// escaped), and the head of a table. The settings' tables have no "For" column.
std::string docs_number(const std::string& toml);
std::string markdown_cell(const std::string& text);
std::string reference_head(bool for_column);

// One row: the key, its type and unit, [who it is for,] its default (from `defaults`, the spec's), what
// is allowed (bounds, or the choices unless the documentation names every one) and what it means.
template <class Item>
std::string reference_row(const SchemaKey<Item>& k, const Item& defaults, bool for_column) {
  const std::string type = k.type + (k.unit.empty() ? "" : " [" + k.unit + "]");
  std::string shown = k.default_text;
  if (shown.empty()) shown = k.required ? "required" : "`" + docs_number(key_text(k, defaults, 2)) + "`";
  std::string allowed = k.direction ? "non-zero" : k.bounds.text(k.type == "integer");
  bool named = true;
  for (const std::string& choice : k.choices) named = named && k.doc.find("`\"" + choice + "\"`") != std::string::npos;
  if (!named)
    for (std::size_t i = 0; i < k.choices.size(); ++i) allowed += (i ? ", `" : "`") + toml_string(k.choices[i]) + "`";
  const std::string meaning = allowed.empty() ? k.doc : k.doc.empty() ? allowed : allowed + "; " + k.doc;
  const std::string for_cell = for_column ? (k.for_text.empty() ? "all" : k.for_text) + " | " : "";
  return "| `" + k.name + "` | " + type + " | " + for_cell + shown + " | " + markdown_cell(meaning) + " |\n";
}

template <class Item>
std::string reference(const std::vector<SchemaKey<Item>>& keys, bool for_column) {
  const Item defaults{};
  std::string table = reference_head(for_column);
  for (const auto& k : keys) table += reference_row(k, defaults, for_column);
  return table;
}

}  // namespace isph
