// libFuzzer target for the trajectory CSV reader: the bytes of a data file go through ReadObservations, the
// reader of `tether gradient --data` and `tether identify --data`, against three fixed models (particles in 2D
// as in docs/examples/identify, a planar rigid body beside a particle, a particle in 3D), so that every kind
// of column name can be recognised.
//
// What may happen: the file is accepted, or an InputError is thrown whose message starts with the file's path.
// Anything else is a finding: another exception, a crash, a sanitizer report, or accepted observations that
// break the header's promises (checked below).
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"

namespace {

// the models the data is read against: only their bodies and their durations matter to the reader
const char* const kScenes[] = {
    R"({"bodies": [{"name": "p0", "type": "particle", "mass": 1, "position": [0.87, 0.5]},
                   {"name": "p1", "type": "particle", "mass": 1.3, "position": [1.37, 1.37]}],
        "simulation": {"duration": 6}})",
    R"({"bodies": [{"name": "bar", "type": "rigid", "mass": 1, "inertia": 0.1, "position": [0, 0.5]},
                   {"name": "bob", "type": "particle", "mass": 1, "position": [1, 0]}],
        "simulation": {"duration": 1}})",
    R"({"dimension": 3, "bodies": [{"name": "bob", "type": "particle", "mass": 1, "position": [1, 0, 0]}],
        "simulation": {"duration": 2.5}})"};

[[noreturn]] void Finding(const std::string& what) {
  std::fprintf(stderr, "trajectory_csv_fuzzer: %s\n", what.c_str());
  std::abort();
}

std::vector<tether::Model<double>>* models = nullptr;
std::string* path = nullptr;

void Cleanup() { std::remove(path->c_str()); }

void CheckObservations(const tether::Observations& obs, const tether::Model<double>& model) {
  if (obs.columns.empty()) Finding("no observed column was accepted");
  for (const tether::TrajectoryColumn& column : obs.columns) {
    if (column.name == "t" || column.name == "constraint_error") Finding("column '" + column.name + "' accepted");
    using Kind = tether::TrajectoryColumn::Kind;
    const int size = column.kind == Kind::kConfiguration ? model.NumCoordinates()
                     : column.kind == Kind::kVelocity    ? model.NumVelocities()
                                                         : 1 << 30;
    if (column.index < 0 || column.index >= size) Finding("column index out of range");
  }
  if (obs.times.empty()) Finding("no rows were accepted");
  if (obs.values.size() != obs.times.size() || obs.lines.size() != obs.times.size()) Finding("row counts differ");
  const double duration = model.simulation.duration;
  for (size_t k = 0; k < obs.times.size(); ++k) {
    if (!(obs.times[k] >= 0 && obs.times[k] <= duration * (1 + 1e-12))) Finding("time outside [0, duration]");
    if (k > 0 && !(obs.times[k] > obs.times[k - 1])) Finding("times not strictly increasing");
    if (obs.values[k].size() != obs.columns.size()) Finding("row size differs from the column count");
    for (double v : obs.values[k]) {
      if (std::isinf(v)) Finding("an infinite value was accepted");
    }
    if (obs.lines[k] < 2) Finding("a data row on line " + std::to_string(obs.lines[k]));
  }
  if (obs.CellCount() < 0) Finding("negative cell count");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  models = new std::vector<tether::Model<double>>;
  for (const char* scene : kScenes) models->push_back(tether::ParseScene(tether::ParseJsonText(scene, "model"), "model").model);
  const char* folder = std::getenv("TMPDIR");
  path = new std::string(std::string(folder && *folder ? folder : "/tmp") + "/tether_fuzz_" +
                         std::to_string(getpid()) + ".csv");
  std::atexit(Cleanup);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // the reader opens a path (as the CLI gives it), so the input goes to a scratch file first
  std::FILE* file = std::fopen(path->c_str(), "wb");
  if (!file || std::fwrite(data, 1, size, file) != size || std::fclose(file) != 0) Finding("cannot write " + *path);
  for (const tether::Model<double>& model : *models) {
    try {
      CheckObservations(tether::ReadObservations(*path, model), model);
    } catch (const tether::InputError& e) {
      const std::string message = e.what();
      if (message.rfind(*path + ": ", 0) != 0) Finding("an input error that does not name the file: " + message);
    }
  }
  return 0;
}
