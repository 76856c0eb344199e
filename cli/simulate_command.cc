#include "simulate_command.h"

#include <iostream>
#include <limits>
#include <sstream>

#include "flags.h"
#include "scene_overrides.h"
#include "scene_run.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"

namespace tether::cli {
namespace {

class SimulateCommand final : public Command {
 public:
  explicit SimulateCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("simulate", "run a scene and write its trajectory CSV");
    app_->add_option("SCENE", scene_path_, "scene file (JSON)")->required();
    overrides_.Register(app_);
    app_->add_option("--every", every_, "write every K-th step (default 1)");
    app_->add_option("-o,--output", output_path_, "CSV file to write (default: stdout)");
    app_->add_option("--events", events_path_,
                     "CSV file of the joint limits' events: t,kind,constraint,speed_before,speed_after");
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    CheckCount(every_, 1, std::numeric_limits<int>::max(), "--every");
    CheckOutputs({{output_path_, "-o"}, {events_path_, "--events"}}, {scene_path_});
    Scene scene = ReadSceneFile(scene_path_);
    overrides_.Apply(&scene.model);

    std::unique_ptr<AtomicOutputFile> file;
    std::ostringstream buffer;  // stdout gets the CSV only once the run has succeeded
    if (!output_path_.empty()) file = std::make_unique<AtomicOutputFile>(output_path_);
    std::unique_ptr<AtomicOutputFile> events;
    if (!events_path_.empty()) events = std::make_unique<AtomicOutputFile>(events_path_);
    std::ostream& out = file ? file->stream() : buffer;
    TrajectoryCsvWriter writer(scene.model, &out);
    RunOptions options;
    options.every = every_;
    const RunReport report = NamingScene(scene_path_, [&] {
      return Simulate<double>(scene.model, options, [&writer](const Sample<double>& s) { writer.Write(s); });
    });
    for (const std::string& warning : report.warnings) std::cerr << "tether: warning: " << scene_path_ << ": " << warning << "\n";
    if (events) {
      WriteEventsCsv(report.events, &events->stream());
      events->Commit();
    }
    if (file) {
      file->Commit();
    } else {
      std::cout << buffer.str() << std::flush;
    }
    return 0;
  }

 private:
  CLI::App* app_;
  std::string scene_path_, output_path_, events_path_;
  SceneOverrides overrides_;
  int every_ = 1;
};

}  // namespace

std::unique_ptr<Command> MakeSimulateCommand(CLI::App* parent) { return std::make_unique<SimulateCommand>(parent); }

}  // namespace tether::cli
