#include "core/expression.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string_view>

namespace isph {

// Operands push one value, functions of one argument replace the top, the rest pop two and push one.
// clang-format off
enum class Expression::Op : std::uint8_t {
  number, x, y, z, t,                             // operands
  neg, sin, cos, tan, exp, log, sqrt, abs, tanh,  // of one argument
  add, sub, mul, div, pow, min, max               // of two
};
// clang-format on

namespace {
constexpr int kMaxStack = 32;    // the evaluation stack; deeper programs are refused when parsing
constexpr int kMaxNesting = 64;  // of parentheses, unary signs and powers, to bound the parser's recursion
}  // namespace

// Recursive descent over expression := term {(+|-) term}, term := unary {(*|/) unary},
// unary := (+|-) unary | primary [^ unary], primary := number | name | name(args) | (expression).
struct Expression::Parser {
  struct Function {
    std::string_view name;
    Op op;
    int arity;
  };
  // clang-format off
  static constexpr std::array<Function, 15> kNames{{
      {"x", Op::x, 0}, {"y", Op::y, 0}, {"z", Op::z, 0}, {"t", Op::t, 0},
      {"sin", Op::sin, 1}, {"cos", Op::cos, 1}, {"tan", Op::tan, 1}, {"exp", Op::exp, 1}, {"log", Op::log, 1},
      {"sqrt", Op::sqrt, 1}, {"abs", Op::abs, 1}, {"tanh", Op::tanh, 1},
      {"min", Op::min, 2}, {"max", Op::max, 2}, {"pow", Op::pow, 2}}};
  // clang-format on
  explicit Parser(const std::string& text) : s(text) {}

  const std::string& s;
  std::size_t i = 0;
  std::vector<Instr> program;
  int depth = 0, nesting = 0;

  [[noreturn]] void fail(const std::string& what, std::size_t at, const std::string& note = "") const {
    throw ExpressionError(what + " at character " + std::to_string(at + 1) + note);
  }
  char peek() {  // the next character after whitespace, '\0' at the end
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    return i < s.size() ? s[i] : '\0';
  }
  bool at_end() { return peek(), i == s.size(); }
  [[noreturn]] void unexpected() {
    if (at_end()) fail("unexpected end of expression", i);
    fail(std::string("unexpected '") + s[i] + "'", i);
  }
  void expect(char c) {
    if (peek() == c) return void(++i);
    if (at_end()) fail(std::string("missing '") + c + "'", i);
    fail(std::string("expected '") + c + "' but found '" + s[i] + "'", i);
  }
  void emit(Op op, double value = 0) {
    program.push_back({op, value});
    depth += op <= Op::t ? 1 : op < Op::add ? 0 : -1;
    if (depth > kMaxStack) fail("expression too deep", i);
  }

  void expression() {
    term();
    for (char c; (c = peek()) == '+' || c == '-';) ++i, term(), emit(c == '+' ? Op::add : Op::sub);
  }
  void term() {
    unary();
    for (char c; (c = peek()) == '*' || c == '/';) ++i, unary(), emit(c == '*' ? Op::mul : Op::div);
  }
  void unary() {
    if (++nesting > kMaxNesting) fail("expression nested too deeply", i);
    if (const char c = peek(); c == '+' || c == '-') {
      ++i, unary();
      if (c == '-') emit(Op::neg);
    } else {
      primary();
      if (peek() == '^') ++i, unary(), emit(Op::pow);  // right-associative, and -2^2 = -(2^2)
    }
    --nesting;
  }
  void primary() {
    const char c = peek();
    const std::size_t at = i;
    if (c == '(') return ++i, expression(), expect(')');
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      double v = 0;
      const auto [end, error] = std::from_chars(s.data() + i, s.data() + s.size(), v);
      if (error != std::errc())
        fail(error == std::errc::result_out_of_range ? "number out of range" : "bad number", at);
      i = end - s.data();
      return emit(Op::number, v);
    }
    if (!std::isalpha(static_cast<unsigned char>(c)) && c != '_') unexpected();
    while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_')) ++i;
    const std::string_view name(s.data() + at, i - at);
    if (name == "pi") return emit(Op::number, std::numbers::pi);
    for (const Function& f : kNames) {
      if (f.name != name) continue;
      if (f.arity == 0) return emit(f.op);
      expect('(');
      int n = 0;
      do expression(), ++n;
      while (peek() == ',' && ++i);
      expect(')');
      if (n != f.arity)
        fail("'" + std::string(name) + "' takes " + std::to_string(f.arity) +
                 (f.arity == 1 ? " argument" : " arguments") + ", not " + std::to_string(n) + ",",
             at);
      return emit(f.op);
    }
    fail("unknown name '" + std::string(name) + "'", at,
         " (variables: x, y, z, t; constants: pi; functions: sin, cos, tan, exp, log, sqrt, abs, min, max, pow, tanh)");
  }
};

Expression Expression::parse(const std::string& text) {
  Parser p(text);
  if (p.at_end()) throw ExpressionError("empty expression");
  p.expression();
  if (!p.at_end()) p.unexpected();
  Expression e;
  e.text_ = text;
  e.program_ = std::move(p.program);
  e.uses_time_ = std::ranges::any_of(e.program_, [](const Instr& in) { return in.op == Op::t; });
  return e;
}

double Expression::operator()(double x, double y, double z, double t) const {
  std::array<double, kMaxStack> s;
  int n = 0;  // the stack's size: s[n - 1] is its top, s[n - 2] below it
  for (const Instr& in : program_) {
    switch (in.op) {
      // clang-format off
      case Op::number: s[n++] = in.value; break;
      case Op::x: s[n++] = x; break;
      case Op::y: s[n++] = y; break;
      case Op::z: s[n++] = z; break;
      case Op::t: s[n++] = t; break;
      case Op::neg: s[n - 1] = -s[n - 1]; break;
      case Op::sin: s[n - 1] = std::sin(s[n - 1]); break;
      case Op::cos: s[n - 1] = std::cos(s[n - 1]); break;
      case Op::tan: s[n - 1] = std::tan(s[n - 1]); break;
      case Op::exp: s[n - 1] = std::exp(s[n - 1]); break;
      case Op::log: s[n - 1] = std::log(s[n - 1]); break;
      case Op::sqrt: s[n - 1] = std::sqrt(s[n - 1]); break;
      case Op::abs: s[n - 1] = std::abs(s[n - 1]); break;
      case Op::tanh: s[n - 1] = std::tanh(s[n - 1]); break;
      case Op::add: --n; s[n - 1] += s[n]; break;
      case Op::sub: --n; s[n - 1] -= s[n]; break;
      case Op::mul: --n; s[n - 1] *= s[n]; break;
      case Op::div: --n; s[n - 1] /= s[n]; break;
      case Op::pow: --n; s[n - 1] = std::pow(s[n - 1], s[n]); break;
      case Op::min: --n; s[n - 1] = std::min(s[n - 1], s[n]); break;
      case Op::max: --n; s[n - 1] = std::max(s[n - 1], s[n]); break;
        // clang-format on
    }
  }
  return n > 0 ? s[0] : 0.0;  // the default expression has no program
}

}  // namespace isph
