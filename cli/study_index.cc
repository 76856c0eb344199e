#include "study_index.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/model/errors.h"
#include "tether/viewer/pages.h"
#include "tether/viewer/view.h"

namespace tether::cli {
namespace {

namespace fs = std::filesystem;

fs::path ViewPath(const std::string& folder, int index) {
  return fs::path(folder) / "views" / (std::to_string(index) + ".js");
}

}  // namespace

RowMotion RowViewWriter(const std::string& folder) {
  return [folder](int index, const std::vector<nlohmann::json>& values, const Model<double>& model,
                  const Trajectory<double>& run) {
    ViewFrames frames;
    try {
      frames = SampledFrames(
          "row " + std::to_string(index), model, run.t, [&](size_t k) { return run.q[k]; },
          {"constraint_error", "energy"},
          [&](size_t k) {
            return std::vector<double>{run.constraint_error[k], Value(run.energy[k])};
          },
          kStudyFramesPerSecond);
    } catch (const InputError&) {  // more than a browser opens (CheckViewSize): the row keeps no view, not the study
      return;
    }
    std::error_code made;  // by the first row (rows run on several threads); writing the file says any failure
    fs::create_directories(fs::path(folder) / "views", made);
    AtomicOutputFile file(ViewPath(folder, index).string());
    file.stream() << StudyRowScript(index, values, model, frames);
    file.Commit();
  };
}

void WriteStudyIndex(const StudySpec& spec, const std::vector<StudyRow>& rows, const std::string& folder) {
  std::vector<std::string> scenes;
  for (size_t k = 0; k < spec.scene_paths.size(); ++k) {
    const std::string path = fs::path(spec.scene_paths[k]).lexically_normal().string();
    scenes.push_back(spec.scene_labels.empty() ? path : spec.scene_labels[k] + " (" + path + ")");
  }
  nlohmann::json study = {
      {"study", spec.path}, {"scenes", scenes}, {"pointers", spec.pointers}, {"metrics", spec.metrics}};
  study["rows"] = nlohmann::json::array();
  for (size_t k = 0; k < rows.size(); ++k) {
    // a row whose run did not finish keeps no motion: a view left by an earlier run of the study goes
    const std::string& status = rows[k].status;
    if (status.rfind("diverged", 0) == 0 || status.rfind("tuning failed", 0) == 0) {
      std::error_code gone;
      fs::remove(ViewPath(folder, static_cast<int>(k)), gone);
    }
    study["rows"].push_back({{"index", k},
                             {"values", rows[k].values},
                             {"metrics", NumbersOrNull(rows[k].metrics)},
                             {"status", rows[k].status},
                             {"view", fs::exists(ViewPath(folder, static_cast<int>(k)))}});
  }
  std::vector<std::string> figures;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() == ".png") figures.push_back(entry.path().filename().string());
  }
  std::sort(figures.begin(), figures.end());
  study["figures"] = figures;
  study["best"] = nlohmann::json::array();  // summary.md's lines on the best rows
  std::ifstream summary(fs::path(folder) / "summary.md");
  for (std::string line; std::getline(summary, line);) {
    if (line.rfind("- ", 0) == 0) study["best"].push_back(line.substr(2));
  }
  AtomicOutputFile file((fs::path(folder) / "index.html").string());
  file.stream() << StudyIndexHtml("tether study " + fs::path(spec.path).filename().string(), study);
  file.Commit();
}

}  // namespace tether::cli
