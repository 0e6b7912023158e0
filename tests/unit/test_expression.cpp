// The arithmetic expressions of case files (core/expression.hpp): precedence, variables, functions, and
// the errors of malformed text, which name the problem and where it is.
#include <gtest/gtest.h>

#include <string>

#include "core/expression.hpp"

using isph::Expression;
using isph::ExpressionError;

namespace {

double eval(const std::string& text, double x = 0, double y = 0, double z = 0, double t = 0) {
  return Expression::parse(text)(x, y, z, t);
}

// The message of the ExpressionError that parsing `text` throws, or "(no error)".
std::string error_of(const std::string& text) {
  try {
    Expression::parse(text);
  } catch (const ExpressionError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Expression, PrecedenceAndAssociativity) {
  EXPECT_DOUBLE_EQ(eval("2+3*4"), 14);
  EXPECT_DOUBLE_EQ(eval("2^3^2"), 512);
  EXPECT_DOUBLE_EQ(eval("-2^2"), -4);
  EXPECT_DOUBLE_EQ(eval("(1+2)*3"), 9);
  EXPECT_DOUBLE_EQ(eval("8/4/2"), 1);
  EXPECT_DOUBLE_EQ(eval("10-4-3"), 3);
  EXPECT_DOUBLE_EQ(eval("2^-1"), 0.5);
  EXPECT_DOUBLE_EQ(eval("--3 + +2"), 5);
  EXPECT_DOUBLE_EQ(eval(" 1e-3 * 2E3 + .5 "), 2.5);
}

TEST(Expression, VariablesAndTheTurekHronParabola) {
  EXPECT_DOUBLE_EQ(eval("x + 10*y + 100*z + 1000*t", 1, 2, 3, 4), 4321);
  const Expression inflow = Expression::parse("1.5 * 4 * y * (0.41 - y) / 0.41^2");
  EXPECT_DOUBLE_EQ(inflow(0, 0.205, 0, 0), 1.5);
  EXPECT_DOUBLE_EQ(inflow(0, 0, 0, 0), 0);
  EXPECT_EQ(inflow.text(), "1.5 * 4 * y * (0.41 - y) / 0.41^2");
  EXPECT_EQ(inflow, Expression::parse("1.5 * 4 * y * (0.41 - y) / 0.41^2"));
}

TEST(Expression, Functions) {
  EXPECT_DOUBLE_EQ(eval("sin(pi/2)"), 1);
  EXPECT_DOUBLE_EQ(eval("max(1,2)"), 2);
  EXPECT_DOUBLE_EQ(eval("min(1, -2)"), -2);
  EXPECT_DOUBLE_EQ(eval("pow(2,10)"), 1024);
  EXPECT_DOUBLE_EQ(eval("sqrt(abs(-16)) + exp(log(3)) + cos(0) + tan(0) + tanh(0)"), 8);
  EXPECT_DOUBLE_EQ(eval("0.5 * (1 - cos(pi * min(t / 2, 1)))", 0, 0, 0, 1), 0.5);
}

TEST(Expression, UsesTime) {
  EXPECT_TRUE(Expression::parse("sin(t)").uses_time());
  EXPECT_FALSE(Expression::parse("x*y + tan(z)").uses_time());
  EXPECT_FALSE(Expression().uses_time());
  EXPECT_DOUBLE_EQ(Expression()(1, 2, 3, 4), 0);  // the default is the constant 0
}

TEST(Expression, ErrorsNameTheProblemAndWhere) {
  EXPECT_THROW(Expression::parse("1+"), ExpressionError);
  const auto has = [](const std::string& text, const std::string& part) {
    const std::string message = error_of(text);
    EXPECT_NE(message.find(part), std::string::npos) << "'" << text << "' gave: " << message;
  };
  has("", "empty expression");
  has("   ", "empty expression");
  has("1+", "unexpected end of expression at character 3");
  has("(1", "missing ')' at character 3");
  has("1)", "unexpected ')' at character 2");
  has("(1+2))*3", "unexpected ')' at character 6");
  has("1 2", "unexpected '2' at character 3");
  has("q", "unknown name 'q' at character 1 (variables: x, y, z, t");
  has("2*qq", "unknown name 'qq' at character 3");
  has("sin(1,2)", "'sin' takes 1 argument, not 2, at character 1");
  has("max(1)", "'max' takes 2 arguments, not 1, at character 1");
  has("sin 1", "expected '(' but found '1' at character 5");
  has("max(1 2)", "expected ')' but found '2' at character 7");
  has("1e999", "number out of range at character 1");
  has(".", "bad number at character 1");
  has(std::string(100, '(') + "1" + std::string(100, ')'), "nested too deeply");
}
