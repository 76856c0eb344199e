// Reading scene files: the JSON text (syntax, nesting, duplicate keys) here, the document through SceneBuilder
// (scene_builder.h).
#include "tether/dynamics/io/scene_reader.h"

#include "scene_builder.h"
#include "tether/dynamics/io/input_file.h"

namespace tether {
namespace reading {
namespace {

// "line L, column C" of byte `end` (0-based) of the text.
std::string LineAndColumn(const std::string& text, size_t end) {
  size_t line = 1, column = 1;
  for (size_t k = 0; k < end && k < text.size(); ++k) {
    if (text[k] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Throws InputError at the first bracket that opens a level deeper than kMaxJsonDepth (strings skipped).
void CheckNesting(const std::string& text, const std::string& path) {
  int depth = 0;
  bool in_string = false;
  for (size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (in_string) {
      if (c == '\\') {
        ++k;  // the escaped character
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        throw InputError(path + ": " + LineAndColumn(text, k) + ": not valid JSON here: nested deeper than " +
                         std::to_string(kMaxJsonDepth) + " levels");
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

// Follows the parser's events to know where it is, and throws InputError at a key an object already has:
// nlohmann::json would keep the last value silently, and a scene whose "mass" is given twice is a mistake.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& path) : path_(path) {}

  bool operator()(int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        frames_.push_back({false, 0, {}, ""});
        break;
      case json::parse_event_t::array_start:
        frames_.push_back({true, 0, {}, ""});
        break;
      case json::parse_event_t::key: {
        Frame& frame = frames_.back();
        frame.key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.key).second) {
          throw InputError(path_ + ": " + Pointer() + ": duplicate key '" + frame.key +
                           "' (a key may appear once in an object)");
        }
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        frames_.pop_back();
        NextElement();
        break;
      case json::parse_event_t::value:
        NextElement();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool array;
    int index;
    std::set<std::string> keys;
    std::string key;
  };

  void NextElement() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }

  std::string Pointer() const {
    std::string pointer;
    for (const Frame& f : frames_) pointer += "/" + (f.array ? std::to_string(f.index) : Escape(f.key));
    return pointer;
  }

  std::string path_;
  std::vector<Frame> frames_;
};

}  // namespace
}  // namespace reading

using reading::json;

json ParseJsonText(const std::string& text, const std::string& path) {
  reading::CheckNesting(text, path);
  try {
    return json::parse(text, reading::DuplicateKeyCheck(path));
  } catch (const json::parse_error& e) {
    // the byte offset is 1-based and points just past the offending character
    const size_t end = std::min(text.size(), e.byte == 0 ? size_t{0} : e.byte - 1);
    std::string what = e.what();
    const size_t colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw InputError(path + ": " + reading::LineAndColumn(text, end) + ": not valid JSON: " + what);
  } catch (const json::exception& e) {  // e.g. a number too large for a double
    std::string what = e.what();
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    throw InputError(path + ": not valid JSON: " + what);
  }
}

Scene ParseScene(const json& document, const std::string& path) {
  Scene scene;
  scene.path = path;
  scene.document = document;
  reading::SceneBuilder(document, path).Build(&scene.model, &scene.numbers);
  return scene;
}

Scene ReadSceneFile(const std::string& path) {
  return ParseScene(ParseJsonText(ReadInputFile(path, "scene file"), path), path);
}

}  // namespace tether