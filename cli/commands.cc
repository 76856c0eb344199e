#include "commands.h"

#include "check_command.h"
#include "gradient_command.h"
#include "identify_command.h"
#include "import_command.h"
#include "simulate_command.h"
#include "study_command.h"
#include "tune_command.h"

namespace tether::cli {

std::vector<std::unique_ptr<Command>> RegisterCommands(CLI::App* app, const std::string& version) {
  app->set_version_flag("--version", version);
  app->require_subcommand(1);
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(MakeSimulateCommand(app));
  commands.push_back(MakeGradientCommand(app));
  commands.push_back(MakeTuneCommand(app));
  commands.push_back(MakeIdentifyCommand(app));
  commands.push_back(MakeFitCommand(app));
  commands.push_back(MakeStudyCommand(app));
  commands.push_back(MakeCheckCommand(app));
  commands.push_back(MakeImportCommand(app));
  return commands;
}

}  // namespace tether::cli
