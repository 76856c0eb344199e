#include "html_text.h"

namespace tether::html {
namespace {

std::string EscapedWith(std::string_view text, bool quotes) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else if (c == '&') {
      out += "&amp;";
    } else if (c == '"' && quotes) {
      out += "&quot;";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

std::string Escaped(std::string_view text) { return EscapedWith(text, false); }

std::string AttributeEscaped(std::string_view text) { return EscapedWith(text, true); }

std::string InScript(std::string_view json_text) {
  std::string out;
  for (size_t i = 0; i < json_text.size(); ++i) {
    out += json_text[i];
    if (json_text[i] == '<' && i + 1 < json_text.size() && json_text[i + 1] == '/') out += '\\';
  }
  return out;
}

void Replace(std::string* page, std::string_view marker, std::string_view text, size_t* from) {
  const size_t at = page->find(marker, *from);
  page->replace(at, marker.size(), text);
  *from = at + text.size();
}

}  // namespace tether::html
