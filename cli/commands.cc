#include "commands.h"

#include <algorithm>

#include "check_command.h"
#include "gradient_command.h"
#include "identify_command.h"
#include "import_command.h"
#include "simulate_command.h"
#include "study_command.h"
#include "tune_command.h"
#include "view_command.h"

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
  commands.push_back(MakeViewCommand(app));
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

// The candidate nearest to `word` by edit distance when it is close enough to be a misspelling of it (within a
// third of its length, or 2), as " (did you mean 'NAME'?)"; else empty.
std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  std::string nearest;
  size_t best = word.size();
  for (const std::string& name : candidates) {
    const size_t distance = EditDistance(word, name);
    if (distance < best) {
      best = distance;
      nearest = name;
    }
  }
  const bool close = !nearest.empty() && best <= std::max<size_t>(2, nearest.size() / 3);
  return close ? " (did you mean '" + nearest + "'?)" : "";
}

}  // namespace

std::string UnexpectedArguments(CLI::App& app, int argc, char** argv) {
  const CLI::App* command = nullptr;
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->parsed()) command = sub;
  }
  std::vector<std::string> left = app.remaining(true);
  if (left.empty()) return "";
  // CLI11 lists them last first: put them in the command line's order, each with where it stood
  std::vector<std::pair<int, std::string>> ordered;
  for (int k = 1; k < argc; ++k) {
    const auto found = std::find(left.begin(), left.end(), argv[k]);
    if (found == left.end()) continue;
    ordered.emplace_back(k, *found);
    left.erase(found);
  }
  for (const std::string& word : left) ordered.emplace_back(-1, word);
  std::vector<std::string> flags;  // the command's long flags, to name the nearest
  if (command) {
    for (const CLI::Option* option : command->get_options()) {
      for (const std::string& name : option->get_lnames()) flags.push_back("--" + name);
    }
  }
  std::string message;
  int after_flag = -2;  // where the last unknown flag stood: the word right after it is its value
  for (const auto& [position, word] : ordered) {
    if (word.rfind("-", 0) != 0 || word == "-") {
      if (position >= 0 && position == after_flag + 1) continue;
      message += (message.empty() ? "" : "; ") + std::string("unexpected argument '") + word + "'";
      continue;
    }
    after_flag = word.find('=') == std::string::npos ? position : -2;
    if (!message.empty()) message += "; ";
    const std::string flag = word.substr(0, word.find('='));
    message += "unknown flag '" + flag + "'" + DidYouMean(flag, flags);
  }
  return (command ? command->get_name() + ": " : std::string()) + message;
}

std::string UnknownCommand(CLI::App& app, const std::string& word) {
  std::vector<std::string> names;
  for (const CLI::App* command : app.get_subcommands({})) {
    if (command->check_name(word)) return "";
    names.push_back(command->get_name());
  }
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return "unknown command '" + word + "'" + DidYouMean(word, names) + "; the commands are " + list;
}

}  // namespace tether::cli
