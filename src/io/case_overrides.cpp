// --set overrides of a case file's keys, applied to the parsed document before it is read.
#include <charconv>
#include <optional>
#include <string_view>

#include "io/case_loading.hpp"
#include "io/case_schema.hpp"

namespace isph::case_loading {

// The offset of the first byte of `text` that does not belong to a well-formed UTF-8 sequence (Unicode
// 15, Table 3-7: no overlong forms, no surrogates, nothing above U+10FFFF), or none. TOML is UTF-8, and
// toml11 3.7's parser reads out of bounds on some malformed sequences (found by fuzzing, docs/RELIABILITY.md),
// so text is checked before it is parsed.
std::optional<std::size_t> first_invalid_utf8(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char b = byte(i);
    // The sequence's length and the allowed range of its second byte, from its lead byte.
    std::size_t length = 1;
    unsigned char low = 0x80, high = 0xBF;
    if (b >= 0x80) {
      if (b >= 0xC2 && b <= 0xDF) {
        length = 2;
      } else if (b >= 0xE0 && b <= 0xEF) {
        length = 3;
        low = b == 0xE0 ? 0xA0 : 0x80;
        high = b == 0xED ? 0x9F : 0xBF;
      } else if (b >= 0xF0 && b <= 0xF4) {
        length = 4;
        low = b == 0xF0 ? 0x90 : 0x80;
        high = b == 0xF4 ? 0x8F : 0xBF;
      } else {
        return i;
      }
    }
    if (i + length > text.size()) return i;
    for (std::size_t k = 1; k < length; ++k) {
      const unsigned char c = byte(i + k);
      if (k == 1 ? (c < low || c > high) : (c < 0x80 || c > 0xBF)) return i;
    }
    i += length;
  }
  return std::nullopt;
}

namespace {

// The value of an override: a TOML value if the text is one, else the text itself as a string (so
// that `structure.integrator=verlet` works unquoted).
toml::value override_value(const std::string& text) {
  std::istringstream in("v = " + text);
  try {
    const toml::value doc = toml::parse(in, "--set");
    if (doc.as_table().size() == 1) return doc.at("v");
  } catch (const std::exception&) {
    // not a TOML value: taken as a string below
  }
  return toml::value(text);
}

// The element of an array named by `segment`: a numeric index, or else the table whose `name` is
// `segment`. Null if there is none.
toml::value* array_element(toml::array& items, const std::string& segment) {
  std::size_t index = 0;
  const char* end = segment.data() + segment.size();
  const auto [ptr, error] = std::from_chars(segment.data(), end, index);
  if (error == std::errc() && ptr == end) return index < items.size() ? &items[index] : nullptr;
  for (auto& item : items)
    if (item.is_table() && item.contains("name") && item.at("name").is_string() &&
        item.at("name").as_string().str == segment)
      return &item;
  return nullptr;
}

}  // namespace

// Sets "dotted.key=value" in `doc`. Missing table keys are created, so that a key outside the
// schema is reported as unknown by the reading that follows. Returns the problem, if any.
std::optional<std::string> apply_override(toml::value& doc, const std::string& text) {
  if (const auto bad = first_invalid_utf8(text)) return "not UTF-8 text (byte " + std::to_string(*bad + 1) + ")";
  const auto equals = text.find('=');
  if (equals == std::string::npos) return "expected key=value";
  const auto segments = split(trim(text.substr(0, equals)), '.');
  if (segments.empty() || std::find(segments.begin(), segments.end(), "") != segments.end())
    return "expected key=value (with a key like kernel.h_factor)";
  toml::value* node = &doc;
  std::string walked;
  for (const auto& segment : segments) {
    if (node->is_table()) {
      node = &node->as_table().try_emplace(segment, toml::table{}).first->second;
    } else if (node->is_array()) {
      node = array_element(node->as_array(), segment);
      if (!node) return walked + ": no element with index or name " + toml_string(segment);
    } else {
      return walked + ": is " + describe(*node) + ", not a table or an array";
    }
    walked += (walked.empty() ? "" : ".") + segment;
  }
  *node = override_value(trim(text.substr(equals + 1)));
  return std::nullopt;
}

}  // namespace isph::case_loading
