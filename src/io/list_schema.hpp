#pragma once
// The keys of the case file's lists and of the tables inside them ([[materials]]; [[bodies]] with their
// shape, clamps, initial_velocity and motion; [[loads]] with their region; [[probes]]) and of
// [periodic], each declared once (list_schema.cpp): name, type, unit, allowed range or choices, default,
// a line of documentation, its place in the element's spec, and the elements it is for (a body's kind,
// a material's model, a motion's type, the dimension). The loader reads and checks them from these
// tables, the resolved case is written from them, and docs/CASES.md's tables of them are generated from
// them (`isph keys`), as for the settings (case_schema.hpp). Rules across the keys of one element (one
// of youngs_modulus and bulk_modulus, min < max) are checked by the loader after its keys.
#include <array>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "io/case.hpp"
#include "io/case_schema.hpp"

namespace isph {

// Where a value key's value lives in its element.
using FieldRef = std::variant<double*, std::string*, std::array<double, 3>*, std::vector<double>*, Shape*,
                              std::vector<Shape>*, MotionSpec*, InitialVelocitySpec*>;

template <class Item>
struct ListKey {
  std::string name;
  std::string type;                  // the docs' type: "float", "string", "vector", "shape", ...
  std::string unit;                  // SI, for the docs
  KeyBounds bounds;                  // a number
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
};

const std::vector<ListKey<MaterialSpec>>& material_keys();
const std::vector<ListKey<BodySpec>>& body_keys();
const std::vector<ListKey<Shape>>& shape_keys();
const std::vector<ListKey<InitialVelocitySpec>>& initial_velocity_keys();
const std::vector<ListKey<MotionSpec>>& motion_keys();
const std::vector<ListKey<LoadSpec>>& load_keys();
const std::vector<ListKey<ProbeSpec>>& probe_keys();
const std::vector<ListKey<PeriodicSpec>>& periodic_keys();

// The TOML text of an element's keys that apply to it, `key = value` each (for the resolved case), and
// of one value as an inline table or array.
std::vector<std::pair<std::string, std::string>> material_entries(const MaterialSpec&, int dimension);
std::vector<std::pair<std::string, std::string>> body_entries(const BodySpec&, int dimension);
std::vector<std::pair<std::string, std::string>> load_entries(const LoadSpec&, int dimension);
std::vector<std::pair<std::string, std::string>> probe_entries(const ProbeSpec&, int dimension);
std::vector<std::pair<std::string, std::string>> periodic_entries(const PeriodicSpec&, int dimension);

// The tables the docs generate: "materials", "bodies", "shape", "initial_velocity", "motion", "loads",
// "probes", "periodic".
const std::vector<std::string>& list_tables();
// The markdown table of one of them.
std::string list_key_reference(const std::string& table);

}  // namespace isph
