#include "tether/studies/study_spec.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "tether/autodiff/parameters.h"
#include "tether/dynamics/io/input_file.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

namespace fs = std::filesystem;
constexpr const char* kStabilizationMethod = "/stabilization/method";

// Where a swept pointer stands in the study file: /sweep/ followed by the pointer escaped as one key (RFC 6901).
std::string SweepEntry(const std::string& pointer) {
  std::string key;
  for (char c : pointer) key += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return "/sweep/" + key;
}

bool IsMetric(const std::string& name) {
  return std::find(std::begin(kStudyMetrics), std::end(kStudyMetrics), name) != std::end(kStudyMetrics);
}

// Writes value at pointer in document. Array elements must exist (writing past the end would pad the array
// with nulls); object keys may be created, so that e.g. /stabilization/method works on a scene without one.
void WriteAt(nlohmann::json* document, const std::string& pointer, const nlohmann::json& value,
             const std::string& study) {
  auto fail = [&](const std::string& why) {
    throw InputError(study + ": " + SweepEntry(pointer) + ": '" + pointer +
                     "' cannot be written into the scene: " + why);
  };
  nlohmann::json::json_pointer at;
  try {
    at = nlohmann::json::json_pointer(pointer);
  } catch (const nlohmann::json::exception&) {
    fail("not a JSON Pointer");
  }
  const nlohmann::json* node = document;
  std::string walked;
  bool created = false;
  for (size_t start = 1; start <= pointer.size() && !created;) {
    const size_t slash = std::min(pointer.find('/', start), pointer.size());
    const std::string token = pointer.substr(start, slash - start);
    if (node->is_array()) {
      char* end = nullptr;
      const long i = std::strtol(token.c_str(), &end, 10);
      if (token.empty() || *end != '\0' || i < 0 || i >= static_cast<long>(node->size())) {
        fail(walked + " has " + std::to_string(node->size()) + " elements, and '" + token + "' is not one of them");
      }
      node = &(*node)[i];
    } else if (node->is_object() && node->contains(token)) {
      node = &(*node)[token];
    } else if (node->is_object() || node->is_null()) {
      created = true;  // the rest of the path is made of new objects
    } else {
      fail(walked + " is not an object or an array");
    }
    walked += "/" + token;
    start = slash + 1;
  }
  try {
    (*document)[at] = value;
  } catch (const nlohmann::json::exception& e) {  // e.g. an empty token where the path has to be made
    fail(std::string("the JSON library refused it (") + e.what() + ")");
  }
}

// Writes a swept value: at its pointer, or, for a pointer that ends in "/*", at every element of that array (as
// --param's wildcard names every element, parameters.h).
void WriteSwept(nlohmann::json* document, const std::string& pointer, const nlohmann::json& value,
                const std::string& study) {
  if (!EndsInWildcard(pointer)) {
    WriteAt(document, pointer, value, study);
    return;
  }
  const std::vector<std::string> elements = WildcardElements(*document, pointer);
  if (elements.empty()) {
    const std::string array = pointer.substr(0, pointer.size() - 2);
    throw InputError(study + ": " + SweepEntry(pointer) + ": '/*' stands for the elements of an array, and " +
                     (array.empty() ? std::string("the scene") : array) + " is not a non-empty array of the scene");
  }
  for (const std::string& element : elements) WriteAt(document, element, value, study);
}

class SpecReader {
 public:
  explicit SpecReader(const std::string& path) : path_(path) {}

  StudySpec Read() {
    ParseJsonText(ReadInputFile(path_, "study file"), path_);  // syntax errors, with their line and column
    // the file's own key order matters for the sweep: read it again, ordered
    const nlohmann::ordered_json study = nlohmann::ordered_json::parse(ReadInputFile(path_, "study file"));
    if (!study.is_object()) Fail("(top level)", "expected an object");
    for (auto it = study.begin(); it != study.end(); ++it) {
      if (it.key() != "scene" && it.key() != "sweep" && it.key() != "metrics" && it.key() != "figures" &&
          it.key() != "ties") {
        Fail("/" + it.key(), "unknown key '" + it.key() + "' (allowed here: scene, sweep, metrics, figures, ties)");
      }
    }
    spec_.path = path_;
    ReadScenes(study.contains("scene") ? study["scene"] : nlohmann::ordered_json());
    ReadSweep(study.contains("sweep") ? study["sweep"] : nlohmann::ordered_json());
    if (study.contains("ties")) ReadTies(study["ties"]);
    ReadMetrics(study.contains("metrics") ? study["metrics"] : nlohmann::ordered_json());
    ReadFigures(study.contains("figures") ? study["figures"] : nlohmann::ordered_json::array({{{"type", "lines"}}}));
    // every combination must make a valid scene: check them now, before any run (errors name the row)
    for (int index = 0; index < RowCount(spec_); ++index) {
      SceneOfRow(spec_, Combination(spec_, index), "row " + std::to_string(index));
    }
    return spec_;
  }

 private:
  [[noreturn]] void Fail(const std::string& pointer, const std::string& message) const {
    throw InputError(path_ + ": " + pointer + ": " + message);
  }

  void AddScene(const std::string& label, const std::string& relative) {
    const std::string path = (fs::path(path_).parent_path() / relative).string();
    spec_.scene_labels.push_back(label);
    spec_.scene_paths.push_back(path);
    spec_.scenes.push_back(ParseJsonText(ReadInputFile(path, "scene file named by " + path_ + "'s /scene"), path));
    ParseScene(spec_.scenes.back(), path);  // each base scene must be valid on its own
  }

  void ReadScenes(const nlohmann::ordered_json& scene) {
    if (scene.is_string()) {
      AddScene("", scene.get<std::string>());
      spec_.scene_labels.clear();
      return;
    }
    if (!scene.is_object() || scene.empty()) {
      Fail("/scene", "expected the scene's path (a string) or {LABEL: path, ...} with at least one scene");
    }
    std::vector<nlohmann::json> labels;
    for (auto it = scene.begin(); it != scene.end(); ++it) {
      if (!it.value().is_string()) Fail("/scene/" + it.key(), "expected a path (a string)");
      AddScene(it.key(), it.value().get<std::string>());
      labels.push_back(it.key());
    }
    spec_.pointers.push_back(kSceneColumn);
    spec_.values.push_back(labels);
  }

  void ReadSweep(const nlohmann::ordered_json& sweep) {
    if (!sweep.is_object() || sweep.empty()) {
      Fail("/sweep", "expected an object {POINTER: [values]} with at least one pointer");
    }
    double rows = 1.0;  // the scene column, when there is one, came first
    for (const std::vector<nlohmann::json>& column : spec_.values) rows *= static_cast<double>(column.size());
    for (auto it = sweep.begin(); it != sweep.end(); ++it) {
      const std::string where = SweepEntry(it.key());
      if (!it.value().is_array() || it.value().empty()) Fail(where, "expected a non-empty array of values");
      try {
        (void)nlohmann::json::json_pointer(it.key());
      } catch (const nlohmann::json::exception&) {
        Fail(where, "'" + it.key() + "' is not a JSON Pointer");
      }
      rows *= static_cast<double>(it.value().size());
      if (rows > kMaxStudyRows) {
        std::ostringstream message;
        message << "the sweep would have " << rows << " rows (the product of its value counts), more than a study "
                << "may run (" << kMaxStudyRows << ")";
        Fail(where, message.str());
      }
      spec_.pointers.push_back(it.key());
      std::vector<nlohmann::json> values;
      for (const auto& v : it.value()) values.push_back(nlohmann::json::parse(v.dump()));
      spec_.values.push_back(values);
    }
  }

  void ReadTies(const nlohmann::ordered_json& ties) {
    if (!ties.is_array()) Fail("/ties", "expected an array of \"PTR=EXPR\" strings");
    for (size_t k = 0; k < ties.size(); ++k) {
      if (!ties[k].is_string()) Fail("/ties/" + std::to_string(k), "expected a \"PTR=EXPR\" string");
      const std::string text = ties[k].get<std::string>();
      RefuseTyingSwept(text.substr(0, text.find('=')), "/ties/" + std::to_string(k));
      spec_.ties.push_back(text);
    }
  }

  // A tie may not set what the sweep sets (the same number, one inside a swept array, or an array holding a swept
  // number): the row would be labelled with the swept value and run with the tied one.
  void RefuseTyingSwept(std::string target, const std::string& where) const {
    if (EndsInWildcard(target)) target.resize(target.size() - 2);
    const auto inside = [](const std::string& inner, const std::string& outer) {
      return inner == outer || inner.rfind(outer + "/", 0) == 0;
    };
    for (const std::string& swept : spec_.pointers) {
      if (swept != kSceneColumn && (inside(target, swept) || inside(swept, target))) {
        Fail(where, "ties " + target + ", which the sweep sets (" + SweepEntry(swept) +
                        "): its rows would be labelled with values they were not run with");
      }
    }
  }

  void ReadMetrics(const nlohmann::ordered_json& metrics) {
    if (!metrics.is_array() || metrics.empty()) Fail("/metrics", "expected a non-empty array of metric names");
    for (size_t k = 0; k < metrics.size(); ++k) {
      const std::string name = metrics[k].is_string() ? metrics[k].get<std::string>() : metrics[k].dump();
      if (!IsMetric(name)) {
        std::string known;
        for (const char* m : kStudyMetrics) known += std::string(known.empty() ? "" : ", ") + m;
        Fail("/metrics/" + std::to_string(k), "unknown metric '" + name + "' (expected one of " + known + ")");
      }
      spec_.metrics.push_back(name);
    }
  }

  // A figure's metric field must name one of the study's metrics.
  void RequireMetric(const nlohmann::ordered_json& figure, const std::string& key, const std::string& where) const {
    if (!figure.contains(key) || !figure[key].is_string()) Fail(where + "/" + key, "expected a metric name");
    const std::string name = figure[key].get<std::string>();
    if (std::find(spec_.metrics.begin(), spec_.metrics.end(), name) == spec_.metrics.end()) {
      Fail(where + "/" + key, "'" + name + "' is not one of this study's /metrics");
    }
  }

  void ReadFigures(const nlohmann::ordered_json& figures) {
    if (!figures.is_array() || figures.empty()) Fail("/figures", "expected a non-empty array of figures");
    for (size_t k = 0; k < figures.size(); ++k) {
      const std::string where = "/figures/" + std::to_string(k);
      const nlohmann::ordered_json& figure = figures[k];
      if (!figure.is_object() || !figure.contains("type") || !figure["type"].is_string()) {
        Fail(where + "/type", "expected a figure type: lines, pareto or gain_map");
      }
      const std::string type = figure["type"].get<std::string>();
      std::vector<std::string> keys = {"type"};
      if (type == "pareto") {
        keys = {"type", "x", "y"};
        RequireMetric(figure, "x", where);
        RequireMetric(figure, "y", where);
      } else if (type == "gain_map") {
        keys = {"type", "color"};
        RequireMetric(figure, "color", where);
        for (const char* gain : {"/stabilization/alpha", "/stabilization/beta"}) {
          if (std::find(spec_.pointers.begin(), spec_.pointers.end(), gain) == spec_.pointers.end()) {
            Fail(where, std::string("a gain_map needs ") + gain + " in /sweep");
          }
        }
      } else if (type != "lines") {
        Fail(where + "/type", "unknown figure type '" + type + "' (expected lines, pareto or gain_map)");
      }
      for (auto it = figure.begin(); it != figure.end(); ++it) {
        if (std::find(keys.begin(), keys.end(), it.key()) == keys.end()) {
          Fail(where + "/" + it.key(), "unknown key '" + it.key() + "' for a " + type + " figure");
        }
      }
      spec_.figures.push_back(nlohmann::json::parse(figure.dump()));
    }
  }

  std::string path_;
  StudySpec spec_;
};

}  // namespace

StudySpec ReadStudySpec(const std::string& path) { return SpecReader(path).Read(); }

int RowCount(const StudySpec& spec) {
  int count = 1;
  for (const auto& v : spec.values) count *= static_cast<int>(v.size());
  return count;
}

std::string CellText(const nlohmann::json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

std::vector<nlohmann::json> Combination(const StudySpec& spec, int index) {
  std::vector<nlohmann::json> values(spec.pointers.size());
  for (int k = static_cast<int>(spec.pointers.size()) - 1; k >= 0; --k) {
    const int n = static_cast<int>(spec.values[k].size());
    values[k] = spec.values[k][index % n];
    index /= n;
  }
  return values;
}

RowScene SceneOfRow(const StudySpec& spec, const std::vector<nlohmann::json>& values, const std::string& row_name) {
  size_t scene = 0;
  for (size_t k = 0; k < spec.pointers.size(); ++k) {
    if (spec.pointers[k] != kSceneColumn) continue;
    const auto& labels = spec.scene_labels;
    scene = std::find(labels.begin(), labels.end(), values[k].get<std::string>()) - labels.begin();
  }
  nlohmann::json document = spec.scenes.at(scene);
  for (size_t k = 0; k < spec.pointers.size(); ++k) {
    if (spec.pointers[k] != kSceneColumn) WriteSwept(&document, spec.pointers[k], values[k], spec.path);
  }
  if (!spec.ties.empty()) {  // the tied numbers follow the row's values (parameters.h's ties, no unknowns)
    const Scene swept = ParseScene(document, spec.path + " (" + row_name + ")");
    ParameterSet tied(swept, {});
    tied.Tie(swept, spec.ties, spec.path + ": /ties");
    tied.WriteInto({}, &document);
  }
  RowScene row;
  const nlohmann::json::json_pointer method(kStabilizationMethod);
  if (document.contains(method) && document[method] == "tuned") {
    row.tune_gains = true;
    document[method] = "baumgarte";
  }
  row.model = ParseScene(document, spec.path + " (" + row_name + ")").model;
  // the reference (rk45 with projection on the row's step grid) ignores the integrator and the stabilization
  if (document.contains("simulation")) {
    for (const char* key : {"integrator", "tolerance", "solver"}) document["simulation"].erase(key);
  }
  document.erase("stabilization");
  row.reference_key = document.dump();
  return row;
}

}  // namespace tether
