// The expression of a tied parameter (`--tie PTR=EXPR`, docs/contract.md): numbers, other scene numbers named by their
// JSON Pointers in braces, + - * / and ^ (power, right-associative, above unary minus: -a^2 = -(a^2)), and
// parentheses:
//   expression := term (('+' | '-') term)*     term := unary (('*' | '/') unary)*
//   unary := '-' unary | power                 power := primary ('^' unary)?
//   primary := NUMBER | '{' POINTER '}' | '(' expression ')'
// Parsed once into postfix order and evaluated for any scalar, so that a tied field follows its references in
// double, with Jets and with Rev alike (its derivative is the chain rule through the expression).
#pragma once

#include <string>
#include <vector>

namespace tether {

class TieExpression {
 public:
  // Throws InputError naming `source` (the flag) and the position of the first character that does not fit.
  TieExpression(const std::string& text, const std::string& source);

  // The pointers the expression names, in order of first appearance; Evaluate takes their values in this order.
  const std::vector<std::string>& references() const { return references_; }

  template <typename T>
  T Evaluate(const std::vector<T>& reference_values) const;

 private:
  struct Token {
    enum class Kind { kNumber, kReference, kAdd, kSubtract, kMultiply, kDivide, kPower, kNegate } kind;
    double number = 0.0;  // kNumber
    int reference = 0;    // kReference: index into references_
  };
  std::vector<Token> postfix_;
  std::vector<std::string> references_;
  friend class TieParser;
};

}  // namespace tether
