// Helpers of the contact tests: a scene parsed under the name contact.json, and its bodies.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tether/dynamics/io/scene_reader.h"

namespace tether {

inline Model<double> Parse(const nlohmann::json& document) { return ParseScene(document, "contact.json").model; }

inline nlohmann::json Particle(const std::string& name, const std::vector<double>& position,
                               const std::vector<double>& velocity = {}) {
  nlohmann::json body = {{"name", name}, {"type", "particle"}, {"mass", 1.0}, {"position", position}};
  if (!velocity.empty()) body["velocity"] = velocity;
  return body;
}

inline nlohmann::json Rigid3d(const std::string& name, const std::vector<double>& position,
                              const std::vector<double>& orientation,
                              const std::vector<double>& angular_velocity = {0.0, 0.0, 0.0}) {
  return {{"name", name},
          {"type", "rigid"},
          {"mass", 2.0},
          {"inertia", {0.02, 0.03, 0.04}},
          {"position", position},
          {"orientation", orientation},
          {"velocity", {0.3, -0.2, 0.5}},
          {"angular_velocity", angular_velocity}};
}

}  // namespace tether
