#pragma once
// The builder of the schema's keys (schema.hpp), shared by the files that declare them: case_schema.cpp
// (the settings), list_schema.cpp (materials, loads, probes, [periodic]) and list_schema_bodies.cpp
// (bodies, their shapes, initial velocities and motions). Internal to those files.
#include <algorithm>
#include <type_traits>

#include "io/list_schema.hpp"

namespace isph::schema_declaration {

using Vec3 = std::array<double, 3>;

inline KeyBounds positive() { return {0, KeyBounds{}.hi, true, true}; }
inline KeyBounds non_negative() { return {0}; }
inline KeyBounds open_unit() { return {0, 1, true, true}; }

inline std::string quoted(const std::string& name) { return toml_string(name); }

// The shape types of a dimension, in the enum's order: the planar ones in 2D, the others in 3D.
inline std::vector<std::string> shape_types(int dimension) {
  std::vector<std::string> names;
  for (const auto& entry : enum_names(ShapeType{}))
    if (is_planar(entry.value) == (dimension == 2)) names.emplace_back(entry.name);
  return names;
}

// `kind = "fluid"`: an element's own value of a choice, for the messages.
template <class E>
std::string is(const std::string& key, E value) {
  return key + " = " + quoted(std::string(name_of(value)));
}

template <class Item>
class Declaration {
 public:
  explicit Declaration(SchemaKey<Item>& key) : key_(key) {}
  Declaration& unit(std::string u) { return key_.unit = std::move(u), *this; }
  Declaration& bounds(KeyBounds b) { return key_.bounds = b, *this; }
  Declaration& choices_in(std::function<std::vector<std::string>(int)> c) {
    return key_.choices_in = std::move(c), *this;
  }
  Declaration& preset(std::function<void(Item&, int)> p) { return key_.preset = std::move(p), *this; }
  Declaration& direction() { return key_.direction = true, *this; }
  Declaration& discriminator() { return key_.discriminator = true, *this; }
  Declaration& required() {
    key_.required = [](const Item&) { return true; };
    return *this;
  }
  Declaration& required_when(std::function<bool(const Item&)> when, std::string text) {
    key_.required = std::move(when);
    key_.default_text = std::move(text);
    return *this;
  }
  // Allowed only for the elements `when` admits; `not_for` says why for another (naming its value).
  Declaration& only(std::function<bool(const Item&, int)> when, std::string for_text,
                    std::function<std::string(const Item&, int)> not_for) {
    key_.applies = std::move(when);
    key_.for_text = std::move(for_text);
    key_.not_for = std::move(not_for);
    return *this;
  }
  Declaration& default_text(std::string text) { return key_.default_text = std::move(text), *this; }
  Declaration& check(std::function<std::string(const Item&, int)> c) { return key_.check = std::move(c), *this; }
  Declaration& written(std::function<bool(const Item&)> w) { return key_.written = std::move(w), *this; }
  Declaration& doc(std::string d) { return key_.doc = std::move(d), *this; }

 private:
  SchemaKey<Item>& key_;
};

// The rule (when, for_text, not_for) of keys for the elements whose `key` (the enum `member`) is one of
// `values`: for_text "edge, traction", not_for "only for type = "edge" or "traction" (type = "point")".
template <class Item, class E>
auto only_where(E Item::*member, const std::string& key, std::vector<E> values) {
  std::string text, message;
  for (std::size_t i = 0; i < values.size(); ++i) {
    text += (i ? ", " : "") + name_of(values[i]);
    message += (i ? " or " : "") + quoted(name_of(values[i]));
  }
  return std::tuple{[member, values](const Item& x, int) {
                      return std::find(values.begin(), values.end(), x.*member) != values.end();
                    },
                    text,
                    [member, key, message](const Item& x, int) {
                      return "only for " + key + " = " + message + " (" + is(key, x.*member) + ")";
                    }};
}

// Declaration::only from a rule (when, for_text, not_for) that several keys of a list share.
template <class Item, class Rule>
Declaration<Item> only(Declaration<Item> d, const Rule& rule) {
  const auto& [when, text, why] = rule;
  d.only(when, text, why);
  return d;
}

template <class T>
constexpr const char* type_text() {
  if constexpr (std::is_same_v<T, bool>) return "boolean";
  if constexpr (std::is_same_v<T, int>) return "integer";
  if constexpr (std::is_same_v<T, double>) return "float";
  if constexpr (std::is_same_v<T, std::string>) return "string";
  if constexpr (std::is_same_v<T, Vec3>) return "vector";
  if constexpr (std::is_same_v<T, std::vector<double>>) return "array of floats";
  if constexpr (std::is_same_v<T, Shape>) return "shape";
  if constexpr (std::is_same_v<T, std::vector<Shape>>) return "array of shapes";
  if constexpr (std::is_same_v<T, MotionSpec>) return "inline table (motion)";
  if constexpr (std::is_same_v<T, InitialVelocitySpec>) return "inline table (initial_velocity)";
  return "";
}

// A key of an element (`section`: a setting's, "" for a list's): its type follows from the member `ref`
// returns (an enum's makes a choice key).
template <class Item, class Ref>
Declaration<Item> add(std::vector<SchemaKey<Item>>& keys, std::string section, std::string name, Ref ref) {
  using T = std::remove_cvref_t<decltype(ref(std::declval<Item&>()))>;
  SchemaKey<Item>& k = keys.emplace_back();
  k.section = std::move(section);
  k.name = std::move(name);
  if constexpr (std::is_enum_v<T>) {
    k.type = "string";
    for (const auto& entry : enum_names(T{})) k.choices.emplace_back(entry.name);
    k.get_name = [ref](const Item& item) { return std::string(name_of(ref(const_cast<Item&>(item)))); };
    k.set_name = [ref](Item& item, const std::string& name) { ref(item) = *enum_from_name<T>(name); };
  } else {
    k.type = type_text<T>();
    k.field = [ref](Item& item) -> FieldRef { return &ref(item); };
  }
  return Declaration<Item>(k);
}

template <class Item, class Ref>
Declaration<Item> add(std::vector<SchemaKey<Item>>& keys, std::string name, Ref ref) {
  return add(keys, "", std::move(name), ref);
}

}  // namespace isph::schema_declaration
