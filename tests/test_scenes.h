// Small scenes built inline for tests (MuJoCo style: build, step, check physics).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/integration/trajectory.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether::testing {

// Parses a scene given as JSON text (throws InputError like a file would).
Model<double> SceneFromJson(const std::string& json_text);

// A stored trajectory (time, q, v, constraint_error, energy, ...) of every output row.
using Recording = Trajectory<double>;
Recording Record(const Model<double>& model, int every = 1);

// The trajectory CSV (header and rows) of the model sampled exactly at `times` (RunOptions::stops).
std::string TrajectoryCsvAt(const Model<double>& model, const std::vector<double>& times);

// Complete elliptic integral of the first kind K(k) = pi / (2 AGM(1, sqrt(1 - k^2))): a pendulum's period.
double EllipticK(double k);

// The simple pendulum of the acceptance checks: a 1 kg bob on a 0.7 m rod, released at rest from 60 degrees.
Model<double> Pendulum60(const std::string& integrator = "rk4", double step = 1e-3, double duration = 1.0);

// The JSON Pointer of every number in a document, in document order (keys hold no '/' or '~' in a scene).
std::vector<std::string> NumberPointers(const nlohmann::json& document);

}  // namespace tether::testing
