#pragma once
// The names a case file gives the values of an enumeration (docs/CASES.md). Beside each such enum E
// stands `enum_names(E)`, found by argument-dependent lookup, returning its EnumName table; the case
// loader turns a name into the value once, and summaries write the name back.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace isph {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

template <class E>
std::string name_of(E value) {
  for (const auto& entry : enum_names(value))
    if (entry.value == value) return std::string(entry.name);
  return "?";
}

template <class E>
std::optional<E> enum_from_name(std::string_view name) {
  for (const auto& entry : enum_names(E{}))
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

}  // namespace isph
