#include "view_command.h"

#include <filesystem>
#include <iostream>

#include "flags.h"
#include "scene_overrides.h"
#include "scene_run.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#ifdef TETHER_HAVE_VIEWER
#include "tether/viewer/view.h"
#endif

namespace tether::cli {
namespace {

class ViewCommand final : public Command {
 public:
  explicit ViewCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("view", "write one HTML file that plays the scene's motion (docs/view.md)");
    app_->add_option("SCENE", scene_path_, "scene file (JSON)")->required();
    overrides_.Register(app_);
    app_->add_option("--data", data_path_, "a trajectory CSV of the scene to play (default: simulate it)");
    app_->add_option("--compare", compare_path_,
                     "a simulated trajectory CSV of the scene to play, with --data's recording drawn as ghosts");
    app_->add_option("-o,--output", output_path_, "HTML file to write")->required();
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
#ifndef TETHER_HAVE_VIEWER
    throw InputError(
        "this tether was built without the viewer (-DTETHER_VIEWER=OFF): install libjs-three and "
        "configure with -DTETHER_VIEWER=ON");
#else
    if (!compare_path_.empty() && data_path_.empty()) {
      throw InputError("--compare: draws a simulation beside the recording --data gives: give --data too");
    }
    CheckOutputs({{output_path_, "-o"}}, {scene_path_, data_path_, compare_path_});
    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);
    ViewFrames frames;
    if (data_path_.empty()) {
      frames = NamingScene(scene_path_, [&] { return SimulatedFrames(scene.model); });
    } else {
      frames = RecordedFrames(scene.model, compare_path_.empty() ? data_path_ : compare_path_);
    }
    for (const std::string& warning : frames.warnings) {
      std::cerr << "tether: warning: " << scene_path_ << ": " << warning << "\n";  // as tether simulate says them
    }
    ViewFrames recording;
    if (!compare_path_.empty()) recording = RecordedFrames(scene.model, data_path_);
    AtomicOutputFile file(output_path_);
    file.stream() << ViewHtml(scene.model, std::filesystem::path(scene_path_).filename().string(), frames,
                              compare_path_.empty() ? nullptr : &recording);
    file.Commit();
    return 0;
#endif
  }

 private:
  CLI::App* app_;
  std::string scene_path_, data_path_, compare_path_, output_path_;
  SceneOverrides overrides_;
};

}  // namespace

std::unique_ptr<Command> MakeViewCommand(CLI::App* parent) { return std::make_unique<ViewCommand>(parent); }

}  // namespace tether::cli
