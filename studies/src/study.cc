#include "tether/studies/study.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "tether/dynamics/errors.h"
#include "tether/dynamics/scene_reader.h"
#include "tether/dynamics/simulator.h"
#include "tether/dynamics/trajectory_csv.h"
#include "tether/tuning/reference.h"

namespace tether {
namespace {

namespace fs = std::filesystem;
const char* const kMetrics[] = {"max_constraint_error", "rms_position_error", "energy_drift", "seconds"};

std::string ReadFile(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the " + what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A swept value as it appears in results.csv.
std::string Cell(const nlohmann::json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

std::string Number(double x) {
  if (std::isnan(x)) return "nan";
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

// The combination of row `index`: the first pointer varies slowest.
std::vector<nlohmann::json> Combination(const StudySpec& spec, int index) {
  std::vector<nlohmann::json> values(spec.pointers.size());
  for (int k = static_cast<int>(spec.pointers.size()) - 1; k >= 0; --k) {
    const int n = static_cast<int>(spec.values[k].size());
    values[k] = spec.values[k][index % n];
    index /= n;
  }
  return values;
}

// Where a swept pointer stands in the study file: /sweep/ followed by the pointer escaped as one key (RFC 6901).
std::string SweepEntry(const std::string& pointer) {
  std::string key;
  for (char c : pointer) key += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return "/sweep/" + key;
}

// Writes value at pointer in document. Array elements must exist (writing past the end would pad the array
// with nulls); object keys may be created, so that e.g. /stabilization/method works on a scene without one.
void WriteAt(nlohmann::json* document, const std::string& pointer, const nlohmann::json& value,
             const std::string& study) {
  auto fail = [&](const std::string& why) {
    throw InputError(study + ": " + SweepEntry(pointer) + ": '" + pointer + "' cannot be written into the scene: " + why);
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
  (*document)[at] = value;
}

// The scene of row `index`: the base scene with the row's values written at the swept pointers, read again with
// the usual validation (errors name the study file and the row). Throws InputError.
Model<double> SceneOfRow(const StudySpec& spec, int index) {
  nlohmann::json document = spec.scene;
  const std::vector<nlohmann::json> values = Combination(spec, index);
  for (size_t k = 0; k < spec.pointers.size(); ++k) WriteAt(&document, spec.pointers[k], values[k], spec.path);
  return ParseScene(document, spec.path + " (row " + std::to_string(index) + ")").model;
}

StudyRow RunRow(const StudySpec& spec, int index) {
  StudyRow row;
  row.values = Combination(spec, index);
  row.metrics.assign(spec.metrics.size(), NAN);
  const Model<double> model = SceneOfRow(spec, index);
  std::vector<Eigen::VectorXd> q;
  double worst = 0.0, energy0 = 0.0, drift = 0.0;
  const auto begin = std::chrono::steady_clock::now();
  try {
    Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
      if (q.empty()) energy0 = s.energy;
      q.push_back(s.q);
      worst = std::max(worst, s.constraint_error);
      drift = std::max(drift, std::abs(s.energy - energy0));
    });
  } catch (const SimulationDiverged& e) {
    row.status = std::string("diverged: ") + e.what();
    return row;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  for (size_t m = 0; m < spec.metrics.size(); ++m) {
    const std::string& name = spec.metrics[m];
    if (name == "max_constraint_error") row.metrics[m] = worst;
    if (name == "energy_drift") row.metrics[m] = drift / std::max(std::abs(energy0), 1.0);
    if (name == "seconds") row.metrics[m] = seconds;
    if (name == "rms_position_error") row.metrics[m] = RmsPositionError(model, ComputeReference(model), q);
  }
  return row;
}

std::string Header(const StudySpec& spec) {
  std::string header;
  for (const std::string& p : spec.pointers) header += p + ",";
  for (const std::string& m : spec.metrics) header += m + ",";
  return header + "status";
}

std::string Line(const StudyRow& row) {
  std::string line;
  for (const nlohmann::json& v : row.values) line += Cell(v) + ",";
  for (double m : row.metrics) line += Number(m) + ",";
  std::string status = row.status;
  std::replace(status.begin(), status.end(), ',', ';');
  std::replace(status.begin(), status.end(), '\n', ' ');
  return line + status;
}

// Rows finished by an earlier, interrupted run: "INDEX,<line>" after a header line equal to ours.
std::map<int, std::string> FinishedRows(const std::string& partial, const std::string& header) {
  std::map<int, std::string> rows;
  std::ifstream in(partial);
  std::string line;
  if (!std::getline(in, line) || line != "index," + header) return rows;
  while (std::getline(in, line)) {
    const size_t comma = line.find(',');
    if (comma == std::string::npos) continue;
    rows[std::atoi(line.substr(0, comma).c_str())] = line.substr(comma + 1);
  }
  return rows;
}

}  // namespace

int RowCount(const StudySpec& spec) {
  int count = 1;
  for (const auto& v : spec.values) count *= static_cast<int>(v.size());
  return count;
}

StudySpec ReadStudySpec(const std::string& path) {
  ParseJsonText(ReadFile(path, "study file"), path);  // syntax errors, with their line and column
  // the file's own key order matters for the sweep: read it again, ordered
  const nlohmann::ordered_json ordered = nlohmann::ordered_json::parse(ReadFile(path, "study file"));
  auto fail = [&path](const std::string& pointer, const std::string& message) {
    throw InputError(path + ": " + pointer + ": " + message);
  };
  if (!ordered.is_object()) fail("(top level)", "expected an object");
  for (auto it = ordered.begin(); it != ordered.end(); ++it) {
    if (it.key() != "scene" && it.key() != "sweep" && it.key() != "metrics") {
      fail("/" + it.key(), "unknown key '" + it.key() + "' (allowed here: scene, sweep, metrics)");
    }
  }
  StudySpec spec;
  spec.path = path;
  if (!ordered.contains("scene") || !ordered["scene"].is_string()) fail("/scene", "expected the scene's path (a string)");
  spec.scene_path = (fs::path(path).parent_path() / ordered["scene"].get<std::string>()).string();
  spec.scene = ParseJsonText(ReadFile(spec.scene_path, "scene file named by " + path + "'s /scene"), spec.scene_path);
  ParseScene(spec.scene, spec.scene_path);  // the base scene must be valid on its own
  if (!ordered.contains("sweep") || !ordered["sweep"].is_object() || ordered["sweep"].empty()) {
    fail("/sweep", "expected an object {POINTER: [values]} with at least one pointer");
  }
  for (auto it = ordered["sweep"].begin(); it != ordered["sweep"].end(); ++it) {
    const std::string where = SweepEntry(it.key());
    if (!it.value().is_array() || it.value().empty()) fail(where, "expected a non-empty array of values");
    try {
      (void)nlohmann::json::json_pointer(it.key());
    } catch (const nlohmann::json::exception&) {
      fail(where, "'" + it.key() + "' is not a JSON Pointer");
    }
    spec.pointers.push_back(it.key());
    std::vector<nlohmann::json> values;
    for (const auto& v : it.value()) values.push_back(nlohmann::json::parse(v.dump()));
    spec.values.push_back(values);
  }
  if (!ordered.contains("metrics") || !ordered["metrics"].is_array() || ordered["metrics"].empty()) {
    fail("/metrics", "expected a non-empty array of metric names");
  }
  for (size_t k = 0; k < ordered["metrics"].size(); ++k) {
    const auto& m = ordered["metrics"][k];
    const std::string name = m.is_string() ? m.get<std::string>() : m.dump();
    if (std::find(std::begin(kMetrics), std::end(kMetrics), name) == std::end(kMetrics)) {
      fail("/metrics/" + std::to_string(k), "unknown metric '" + name +
                                                "' (expected max_constraint_error, rms_position_error, energy_drift or seconds)");
    }
    spec.metrics.push_back(name);
  }
  // every combination must make a valid scene: check them now, before any run (errors name the row)
  for (int index = 0; index < RowCount(spec); ++index) SceneOfRow(spec, index);
  return spec;
}

std::vector<StudyRow> RunStudy(const StudySpec& spec, const std::string& folder, int threads,
                               const std::function<void(int, int, double)>& progress) {
  fs::create_directories(folder);
  const std::string header = Header(spec);
  const std::string partial = (fs::path(folder) / "results.partial.csv").string();
  const int total = RowCount(spec);
  std::map<int, std::string> finished = FinishedRows(partial, header);
  std::vector<std::string> lines(total);
  for (const auto& [index, line] : finished) {
    if (index >= 0 && index < total) lines[index] = line;
  }
  std::ofstream log(partial, finished.empty() ? std::ios::trunc : std::ios::app);
  if (finished.empty()) log << "index," << header << "\n" << std::flush;

  std::vector<int> todo;
  for (int i = 0; i < total; ++i) {
    if (lines[i].empty()) todo.push_back(i);
  }
  std::atomic<size_t> next{0};
  std::mutex mutex;
  int done = total - static_cast<int>(todo.size());
  const auto start = std::chrono::steady_clock::now();
  std::string failure;
  auto work = [&] {
    for (size_t k; (k = next++) < todo.size();) {
      std::string line;
      try {
        line = Line(RunRow(spec, todo[k]));
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mutex);
        failure = e.what();
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      lines[todo[k]] = line;
      log << todo[k] << "," << line << "\n" << std::flush;
      ++done;
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const int ran = done - (total - static_cast<int>(todo.size()));
      progress(done, total, elapsed / std::max(1, ran) * (total - done));
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, std::min(threads, static_cast<int>(todo.size()))); ++t) pool.emplace_back(work);
  for (std::thread& t : pool) t.join();
  log.close();
  if (!failure.empty()) throw std::runtime_error(failure);

  AtomicOutputFile out((fs::path(folder) / "results.csv").string());
  out.stream() << header << "\n";
  for (const std::string& line : lines) out.stream() << line << "\n";
  out.Commit();
  fs::remove(partial);

  std::vector<StudyRow> rows(total);
  for (int i = 0; i < total; ++i) {
    rows[i].values = Combination(spec, i);
    std::stringstream cells(lines[i]);
    std::string cell;
    for (size_t k = 0; k < spec.pointers.size(); ++k) std::getline(cells, cell, ',');
    for (size_t m = 0; m < spec.metrics.size(); ++m) {
      std::getline(cells, cell, ',');
      rows[i].metrics.push_back(cell == "nan" ? NAN : std::strtod(cell.c_str(), nullptr));
    }
    std::getline(cells, rows[i].status);
  }
  return rows;
}

}  // namespace tether
