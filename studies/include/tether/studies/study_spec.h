// STUDY.json: what a study sweeps, what it measures and what it draws (studies/README.md, "The study file").
//
//   {"scene": PATH | {LABEL: PATH, ...},     paths relative to STUDY.json
//    "sweep": {PTR: [values], ...},          JSON Pointers into the scene, swept in the file's key order
//    "metrics": [names],
//    "figures": [{"type": "lines"} | {"type": "pareto", "x": METRIC, "y": METRIC}
//                | {"type": "gain_map", "color": METRIC}],   optional; default [{"type": "lines"}]
//    "ties": ["PTR=EXPR", ...]}             optional: numbers that follow others, as --tie (parameters.h)
//
// A row is one combination of the swept values, the first column varying slowest. With several labelled scenes
// the first column is `scene` (the label), then the pointers. Each value is written into the scene at its
// pointer (at every element of the array for a pointer ending in "/*"), the ties are set from the result, and the
// scene is read again with the usual validation; the value "tuned" at /stabilization/method
// asks for Baumgarte with the gains `tether tune` finds for that row's scene.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tether/dynamics/model/model.h"

namespace tether {

inline constexpr const char* kSceneColumn = "scene";

// The metrics a study can ask for (study.h says what each measures).
inline constexpr const char* kStudyMetrics[] = {"max_constraint_error",
                                                "rms_position_error",
                                                "energy_drift",
                                                "seconds",
                                                "seconds_per_simulated_second",
                                                "alpha",
                                                "beta",
                                                "events"};

struct StudySpec {
  std::string path;                                 // STUDY.json, for messages
  std::vector<std::string> scene_labels;            // empty for a single unlabelled scene
  std::vector<std::string> scene_paths;             // resolved against STUDY.json's folder
  std::vector<nlohmann::json> scenes;               // the base scene documents
  std::vector<std::string> pointers;                // the swept columns: `scene` (when labelled), then pointers
  std::vector<std::vector<nlohmann::json>> values;  // per column
  std::vector<std::string> metrics;
  std::vector<nlohmann::json> figures;              // validated figure requests
  std::vector<std::string> ties;                    // "PTR=EXPR": numbers that follow the swept ones (--tie)
};

// Reads and validates STUDY.json, its scenes and every combination of the sweep. Throws InputError naming the
// file and the JSON Pointer (and the row) at fault.
StudySpec ReadStudySpec(const std::string& path);

// The number of rows, the product of the columns' value counts; ReadStudySpec refuses more than kMaxStudyRows.
inline constexpr int kMaxStudyRows = 1'000'000;
int RowCount(const StudySpec& spec);

// A swept value as results.csv writes it: a string as it is, anything else as JSON.
std::string CellText(const nlohmann::json& value);

// The swept values of row `index`, one per column.
std::vector<nlohmann::json> Combination(const StudySpec& spec, int index);

// The scene of a row: the base scene with `values` written at the swept pointers (Combination's order).
struct RowScene {
  Model<double> model;
  bool tune_gains = false;     // /stabilization/method was "tuned"
  std::string reference_key;  // equal for rows that share a reference motion (all but integrator and stabilization)
};
RowScene SceneOfRow(const StudySpec& spec, const std::vector<nlohmann::json>& values, const std::string& row_name);

}  // namespace tether
