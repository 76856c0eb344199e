#include "tether/autodiff/tie_expression.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <utility>

#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/scalars/scalar.h"

namespace tether {

// Recursive descent over the grammar in tie_expression.h, emitting postfix tokens.
class TieParser {
 public:
  TieParser(const std::string& text, const std::string& source, TieExpression* out)
      : text_(text), source_(source), out_(out) {}

  void Parse() {
    Expression();
    Skip();
    if (at_ != text_.size()) Fail("unexpected '" + std::string(1, text_[at_]) + "'");
    if (out_->postfix_.empty()) Fail("an empty expression");
  }

 private:
  using Kind = TieExpression::Token::Kind;

  [[noreturn]] void Fail(const std::string& why) const {
    throw InputError(source_ + ": " + why + " at character " + std::to_string(at_ + 1) + " of '" + text_ + "'");
  }
  void Skip() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool Take(char c) {
    Skip();
    if (at_ < text_.size() && text_[at_] == c) {
      ++at_;
      return true;
    }
    return false;
  }
  void Emit(Kind kind) { out_->postfix_.push_back({kind}); }

  // operand (op operand)*, left-associative, over the operators given
  template <typename Operand>
  void LeftAssociative(Operand operand, std::initializer_list<std::pair<char, Kind>> operators) {
    operand();
    for (bool more = true; more;) {
      more = false;
      for (const auto& [symbol, kind] : operators) {
        if (!Take(symbol)) continue;
        operand();
        Emit(kind);
        more = true;
        break;
      }
    }
  }
  void Expression() {
    LeftAssociative([this] { Term(); }, {{'+', Kind::kAdd}, {'-', Kind::kSubtract}});
  }
  void Term() {
    LeftAssociative([this] { Unary(); }, {{'*', Kind::kMultiply}, {'/', Kind::kDivide}});
  }
  // Every nesting (a parenthesis, a sign, a power's exponent) passes here: bounded, so that no input can
  // exhaust the stack.
  void Unary() {
    if (++depth_ > kMaxDepth) Fail("an expression nested more than " + std::to_string(kMaxDepth) + " deep");
    Nested();
    --depth_;
  }
  void Nested() {
    if (Take('-')) {
      Unary();
      Emit(Kind::kNegate);
      return;
    }
    Power();
  }
  void Power() {
    Primary();
    if (Take('^')) {
      Unary();
      Emit(Kind::kPower);
    }
  }
  void Primary() {
    Skip();
    if (Take('(')) {
      Expression();
      if (!Take(')')) Fail("expected ')'");
      return;
    }
    if (Take('{')) {
      const size_t close = text_.find('}', at_);
      if (close == std::string::npos) Fail("a '{' without its '}'");
      const std::string pointer = text_.substr(at_, close - at_);
      if (pointer.empty() || pointer[0] != '/') Fail("expected a JSON Pointer (starting with '/') in braces");
      auto& refs = out_->references_;
      const auto found = std::find(refs.begin(), refs.end(), pointer);
      const int index = static_cast<int>(found - refs.begin());
      if (found == refs.end()) refs.push_back(pointer);
      out_->postfix_.push_back({Kind::kReference, 0.0, index});
      at_ = close + 1;
      return;
    }
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double number = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(number)) Fail("expected a number, a {pointer} or '('");
    out_->postfix_.push_back({Kind::kNumber, number, 0});
    at_ += static_cast<size_t>(end - begin);
  }

  const std::string& text_;
  const std::string& source_;
  TieExpression* out_;
  size_t at_ = 0;
  int depth_ = 0;
  static constexpr int kMaxDepth = 200;
};

TieExpression::TieExpression(const std::string& text, const std::string& source) {
  TieParser(text, source, this).Parse();
}

template <typename T>
T TieExpression::Evaluate(const std::vector<T>& reference_values) const {
  using std::pow;
  std::vector<T> stack;
  stack.reserve(postfix_.size());
  for (const Token& token : postfix_) {
    if (token.kind == Token::Kind::kNumber) {
      stack.push_back(T(token.number));
      continue;
    }
    if (token.kind == Token::Kind::kReference) {
      stack.push_back(reference_values[token.reference]);
      continue;
    }
    if (token.kind == Token::Kind::kNegate) {
      stack.back() = -stack.back();
      continue;
    }
    const T right = stack.back();
    stack.pop_back();
    T& left = stack.back();
    switch (token.kind) {
      case Token::Kind::kAdd:
        left = left + right;
        break;
      case Token::Kind::kSubtract:
        left = left - right;
        break;
      case Token::Kind::kMultiply:
        left = left * right;
        break;
      case Token::Kind::kDivide:
        left = left / right;
        break;
      default:  // kPower
        left = pow(left, right);
        break;
    }
  }
  return stack.back();
}

template double TieExpression::Evaluate<double>(const std::vector<double>&) const;
template Jet TieExpression::Evaluate<Jet>(const std::vector<Jet>&) const;
template Rev TieExpression::Evaluate<Rev>(const std::vector<Rev>&) const;

}  // namespace tether
