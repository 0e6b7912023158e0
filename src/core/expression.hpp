#pragma once
// A small arithmetic expression of x, y, z and t, read from a case file: the inflow profiles of open
// boundaries (docs/CASES.md). It is parsed once into a postfix program, which is then evaluated per
// particle in a tight loop on a small fixed stack, without recursion or allocation.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace isph {

// A text that does not parse; what() says what is wrong and at which character (counted from 1).
struct ExpressionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A parsed expression of the variables x, y, z and t.
class Expression {
 public:
  Expression() = default;  // the constant 0
  // Numbers, + - * / ^ (right-associative, above unary minus), parentheses, x y z t pi, and the functions
  // sin cos tan exp log sqrt abs tanh of one argument and min max pow of two. Throws ExpressionError.
  static Expression parse(const std::string& text);
  double operator()(double x, double y, double z, double t) const;
  const std::string& text() const { return text_; }
  bool uses_time() const { return uses_time_; }  // whether t appears
  bool operator==(const Expression& o) const { return text_ == o.text_; }

 private:
  enum class Op : std::uint8_t;  // the instructions, in expression.cpp
  struct Instr {
    Op op;
    double value;  // of a number
  };
  struct Parser;
  std::string text_ = "0";
  std::vector<Instr> program_;  // postfix; empty for the constant 0
  bool uses_time_ = false;
};

}  // namespace isph
