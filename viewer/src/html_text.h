// Text put into the pages' HTML: element content, attribute values, script bodies, and the templates' markers.
#pragma once

#include <string>
#include <string_view>

namespace tether::html {

// Text for an element's content: < > & escaped.
std::string Escaped(std::string_view text);

// Text for a double-quoted attribute's value (an iframe's srcdoc): < > & " escaped.
std::string AttributeEscaped(std::string_view text);

// A script's text never holds "</" (which could end its element early): JSON may write "<\/", JavaScript
// libraries are inlined as they are (three.js holds none).
std::string InScript(std::string_view json_text);

// Replaces the first `marker` at or after *from, and moves *from past the text put in: no inlined text (a body
// named @PLAYER@) is searched again.
void Replace(std::string* page, std::string_view marker, std::string_view text, size_t* from);

}  // namespace tether::html
