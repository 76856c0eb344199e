// libFuzzer target for the command-line parser: the input, split at line breaks into at most 64 arguments,
// is parsed as `tether ARGS` by the same CLI11 app main.cc builds (every subcommand and flag registered by
// RegisterCommands), and a first argument or a refused parse gets main's messages (UnknownCommand,
// UnexpectedArguments). Nothing runs: this is the parser alone.
//
// What may happen: the arguments parse, or CLI11 refuses them with one of its errors (which main turns into exit
// status 2 and a message, or prints --help / --version). Anything else is a finding: another exception, a crash,
// a sanitizer report.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "commands.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> arguments = {"tether"};
  std::string current;
  for (size_t k = 0; k < size && arguments.size() <= 64; ++k) {
    if (data[k] == '\n') {
      arguments.push_back(current);
      current.clear();
    } else {
      current += static_cast<char>(data[k]);
    }
  }
  if (!current.empty() && arguments.size() <= 64) arguments.push_back(current);
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  CLI::App app{"tether"};
  const auto commands = tether::cli::RegisterCommands(&app, "tether fuzz");
  try {
    if (argv.size() > 1) tether::cli::UnknownCommand(app, argv[1]);
    try {
      app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::ParseError&) {  // refused (or --help, --version): main's message
      tether::cli::UnexpectedArguments(app, static_cast<int>(argv.size()), argv.data());
    }
  } catch (const CLI::Error&) {  // main's handled cases
  } catch (const std::exception& e) {
    std::fprintf(stderr, "command_line_fuzzer: an exception CLI11 did not raise: %s\n", e.what());
    std::abort();
  }
  return 0;
}
