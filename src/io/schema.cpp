#include "io/schema.hpp"

#include <charconv>
#include <cstdio>

#include "io/list_schema.hpp"

namespace isph {

std::string KeyBounds::text(bool integer) const {
  const bool has_lo = lo > -std::numeric_limits<double>::infinity();
  const bool has_hi = hi < std::numeric_limits<double>::infinity();
  const auto whole = [](double x) { return std::to_string(static_cast<long long>(x)); };
  if (integer && has_lo && has_hi) return "in " + whole(lo) + ".." + whole(hi);
  if (integer && has_lo && lo == 1 && !lo_open) return "> 0";
  const std::string low = std::string(lo_open ? "> " : ">= ") + shortest_number(lo);
  const std::string high = std::string(hi_open ? "< " : "<= ") + shortest_number(hi);
  if (has_lo && has_hi) return low + " and " + high;
  return has_lo ? low : has_hi ? high : "";
}

std::string shortest_number(double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string toml_float(double x) {
  std::string text = shortest_number(x);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text;
}

std::string toml_string(const std::string& s) {
  std::string text = "\"";
  for (const char ch : s) {
    const auto code = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      text += '\\';
      text += ch;
    } else if (code < 0x20 || code == 0x7f) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", code);
      text += escape;
    } else {
      text += ch;
    }
  }
  return text + "\"";
}

std::string toml_vector(const std::array<double, 3>& v, int dimension) {
  std::string text = "[";
  for (int k = 0; k < dimension; ++k) text += (k ? ", " : "") + toml_float(v[k]);
  return text + "]";
}

std::string one_of(const std::vector<std::string>& allowed) {
  std::string text = "must be one of ";
  for (std::size_t i = 0; i < allowed.size(); ++i) text += (i ? ", " : "") + toml_string(allowed[i]);
  return text;
}

namespace {

std::string inline_table(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::string text = "{ ";
  for (std::size_t i = 0; i < entries.size(); ++i)
    text += (i ? ", " : "") + entries[i].first + " = " + entries[i].second;
  return text + " }";
}

}  // namespace

std::string value_text(const FieldRef& field, int dimension) {
  struct Text {
    int d;
    std::string operator()(bool* b) const { return *b ? "true" : "false"; }
    std::string operator()(int* i) const { return std::to_string(*i); }
    std::string operator()(double* x) const { return toml_float(*x); }
    std::string operator()(std::string* s) const { return toml_string(*s); }
    std::string operator()(std::array<double, 3>* v) const { return toml_vector(*v, d); }
    std::string operator()(std::vector<double>* v) const {
      std::string text = "[";
      for (std::size_t i = 0; i < v->size(); ++i) text += (i ? ", " : "") + toml_float((*v)[i]);
      return text + "]";
    }
    std::string operator()(Shape* s) const { return inline_table(entries(*s, shape_keys(), d)); }
    std::string operator()(std::vector<Shape>* shapes) const {
      std::string text = "[";
      for (std::size_t i = 0; i < shapes->size(); ++i) text += (i ? ", " : "") + (*this)(&(*shapes)[i]);
      return text + "]";
    }
    std::string operator()(MotionSpec* m) const { return inline_table(entries(*m, motion_keys(), d)); }
    std::string operator()(InitialVelocitySpec* v) const {
      return inline_table(entries(*v, initial_velocity_keys(), d));
    }
  };
  return std::visit(Text{dimension}, field);
}

std::string docs_number(const std::string& toml) {
  std::string text = toml;
  const auto e = text.find('e');
  const bool number = !text.empty() && (text.front() == '-' || (text.front() >= '0' && text.front() <= '9'));
  if (!number || e == std::string::npos) return text;
  std::size_t digits = e + 1;
  if (digits < text.size() && (text[digits] == '-' || text[digits] == '+')) ++digits;
  while (digits + 1 < text.size() && text[digits] == '0') text.erase(digits, 1);
  return text;
}

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string reference_head(bool for_column) {
  return for_column ? "| Key | Type | For | Default | Allowed / meaning |\n|---|---|---|---|---|\n"
                    : "| Key | Type | Default | Allowed / meaning |\n|---|---|---|---|\n";
}

}  // namespace isph
