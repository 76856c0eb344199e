// tether: the command-line front end. Exit status 0 on success, 1 when a run fails (diverges, an output cannot
// be written, the machine refuses memory or threads), 2 on bad input or usage, always with a message on stderr;
// an interruption (SIGINT, SIGTERM, SIGHUP) leaves no temporary file behind (interrupts.h).
#include <iostream>
#include <memory>
#include <new>
#include <nlohmann/json.hpp>
#include <system_error>
#include <vector>

#include "commands.h"
#include "matplotlib_script.h"
#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/model/errors.h"

int main(int argc, char** argv) {
  using namespace tether;
  CLI::App app{"tether: constrained multibody dynamics in maximal coordinates, differentiable end to end"};
  const std::string commit = TETHER_COMMIT;
  const std::vector<std::unique_ptr<cli::Command>> commands = cli::RegisterCommands(
      &app, std::string("tether ") + TETHER_VERSION + (commit.empty() ? "" : " (commit " + commit + ")"));
  InstallInterruptHandlers();
  if (argc > 1 && argv[1][0] != '-') {  // CLI11 would answer a misspelled command "A subcommand is required"
    const std::string unknown = cli::UnknownCommand(app, argv[1]);
    if (!unknown.empty()) {
      std::cerr << "tether: " << unknown << "\n(run 'tether --help' for usage)\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // a misspelled flag first: it is often why a required one is missing too
    const std::string unexpected = cli::UnexpectedArguments(app, argc, argv);
    if (!unexpected.empty()) std::cerr << "tether: " << unexpected << "\n";
    if (unexpected.empty() || !dynamic_cast<const CLI::ExtrasError*>(&e)) std::cerr << "tether: " << e.what() << "\n";
    std::cerr << "(run 'tether --help' for usage)\n";
    return 2;
  }
  for (const auto& command : commands) {
    if (!command->app()->parsed()) continue;
    try {
      const int status = command->Run();
      std::cout.flush();
      if (!std::cout) throw OutputError("cannot write to standard output");
      return status;
    } catch (const cli::DrawingInterrupted& e) {
      std::cerr << "tether: interrupted while drawing the figures; what was written before them is complete\n";
      EndAsSignal(e.signal());
    } catch (const InputError& e) {
      std::cerr << "tether: error: " << e.what() << "\n";
      return 2;
    } catch (const SimulationDiverged& e) {
      std::cerr << "tether: " << e.what() << "\n";
      return 1;
    } catch (const OutputError& e) {
      std::cerr << "tether: error: " << e.what() << "\n";
      return 1;
    } catch (const std::bad_alloc&) {
      std::cerr << "tether: failed: out of memory\n";
      return 1;
    } catch (const std::system_error& e) {  // e.g. threads that cannot be started
      std::cerr << "tether: failed: the system refused: " << e.what() << "\n";
      return 1;
    } catch (const nlohmann::json::exception& e) {  // every input is checked before the JSON library sees it
      std::cerr << "tether: internal error (a bug in tether: please report the command): " << e.what() << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "tether: failed: " << e.what() << "\n";
      return 1;
    }
  }
  return 2;
}
