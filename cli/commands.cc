#include "commands.h"

#include <algorithm>

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

namespace {

// The Levenshtein distance: insertions, deletions and substitutions that turn a into b.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string UnknownCommand(CLI::App& app, const std::string& word) {
  std::string names, nearest;
  size_t best = word.size();
  for (const CLI::App* command : app.get_subcommands({})) {
    if (command->check_name(word)) return "";
    const std::string& name = command->get_name();
    names += (names.empty() ? "" : ", ") + name;
    const size_t distance = EditDistance(word, name);
    if (distance < best) {
      best = distance;
      nearest = name;
    }
  }
  const bool close = !nearest.empty() && best <= std::max<size_t>(2, nearest.size() / 3);
  return "unknown command '" + word + "'" + (close ? " (did you mean '" + nearest + "'?)" : "") +
         "; the commands are " + names;
}

}  // namespace tether::cli
