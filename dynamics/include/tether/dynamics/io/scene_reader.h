// Reading scene files (docs/contract.md, documented in docs/scene-format.md) into Model<double>, with the record
// of which JSON Pointer landed in which model field (scene_numbers.h).
//
// Validation is strict: an unknown key anywhere, a wrong type, a number out of range, an unknown body, a
// duplicate name, a wrong vector length are all errors. Every error is an InputError whose message starts with
// the file name and the JSON Pointer of the offending value ("scene.json: /bodies/0/mass: must be > 0, got -1"),
// or, for a syntax error, the line and column the JSON parser stopped at.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "tether/dynamics/io/scene_numbers.h"
#include "tether/dynamics/model/model.h"

namespace tether {

struct Scene {
  std::string path;         // as given, for messages
  nlohmann::json document;  // the file as read (for writing scenes back with changed values)
  Model<double> model;
  SceneNumbers numbers;  // where each number of the document landed in the model (the parameters' binding)
};

// Reads and validates a scene file. Throws InputError.
Scene ReadSceneFile(const std::string& path);

// Validates an already parsed document; `path` only names it in messages. Throws InputError.
Scene ParseScene(const nlohmann::json& document, const std::string& path);

// Parses JSON text, turning a syntax error into an InputError naming `path`, the line and the column. Arrays and
// objects nested deeper than kMaxJsonDepth are refused the same way before parsing (a scene needs five levels;
// tens of thousands would exhaust the stack of the recursive parts of the JSON library). A key repeated in one
// object is an InputError naming its JSON Pointer, as an unknown key is.
inline constexpr int kMaxJsonDepth = 256;
nlohmann::json ParseJsonText(const std::string& text, const std::string& path);

}  // namespace tether
