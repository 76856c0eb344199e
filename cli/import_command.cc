#include "import_command.h"

#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "flags.h"
#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::cli {
namespace {

// "NAME=VALUE" given with `flag`, VALUE a finite number.
std::pair<std::string, double> NameAndNumber(const std::string& text, const std::string& flag) {
  const size_t equals = text.rfind('=');
  const std::string name = equals == std::string::npos ? "" : text.substr(0, equals);
  const std::string number = equals == std::string::npos ? "" : text.substr(equals + 1);
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(number.c_str(), &end);
  if (name.empty() || number.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
    throw InputError(flag + " " + text + ": expected NAME=VALUE with a finite number");
  }
  return {name, value};
}

// JSON with one line per key of an object, and small values (numbers, vectors, a pair of points) on one line.
void Write(const nlohmann::ordered_json& value, int depth, std::ostream* out) {
  const std::string flat = value.dump();
  const std::string indent(2 * depth + 2, ' ');
  if (flat.size() + indent.size() <= 110 || !value.is_structured() || value.empty()) {
    *out << flat;
    return;
  }
  const bool object = value.is_object();
  *out << (object ? "{" : "[");
  bool first = true;
  for (auto it = value.begin(); it != value.end(); ++it) {
    *out << (first ? "\n" : ",\n") << indent;
    if (object) *out << nlohmann::ordered_json(it.key()).dump() << ": ";
    Write(*it, depth + 1, out);
    first = false;
  }
  *out << "\n" << std::string(2 * depth, ' ') << (object ? "}" : "]");
}

class ImportCommand final : public Command {
 public:
  explicit ImportCommand(CLI::App* parent) {
    app_ = parent->add_subcommand("import", "make a tether scene from an MJCF (.xml) or URDF (.urdf) model");
    app_->add_option("MODEL", model_path_, "the model: MJCF (.xml, compiled by MuJoCo) or URDF (.urdf)")->required();
    app_->add_option("-o,--output", output_path_, "scene file to write (default: stdout)");
    app_->add_option("--joint", joint_values_, "NAME=VALUE: a hinge's (rad) or slide's (m) initial coordinate");
    app_->add_option("--joint-velocity", joint_rates_, "NAME=RATE: a hinge's (rad/s) or slide's (m/s) initial rate");
    app_->add_option("--fix", options_.fixed_bodies,
                     "BODY: make it part of the world where it starts, in place of its joints");
    app_->add_flag("--merge-fixed", options_.merge_fixed, "merge links welded to their parent into its body");
    app_->add_flag("--split-joints", options_.split_joints,
                   "keep every model joint as its own constraint (through light intermediate bodies)");
    app_->add_flag_callback(
        "--no-contact", [this] { options_.contact = false; },
        "keep the collision shapes as drawn only (\"contact\": false): no contact is simulated");
  }

  CLI::App* app() const override { return app_; }

  int Run() override {
    for (const std::string& text : joint_values_) options_.joint_values.push_back(NameAndNumber(text, "--joint"));
    for (const std::string& text : joint_rates_) options_.joint_rates.push_back(NameAndNumber(text, "--joint-velocity"));
    CheckOutputs({{output_path_, "-o"}}, {model_path_});
    const importers::ImportedScene imported = importers::ImportModel(model_path_, options_);
    for (const std::string& warning : imported.warnings) {
      std::cerr << "tether: warning: " << model_path_ << ": " << warning << "\n";
    }
    std::ostringstream text;
    Write(imported.scene, 0, &text);
    text << "\n";
    if (output_path_.empty()) {
      std::cout << text.str() << std::flush;
      return 0;
    }
    AtomicOutputFile file(output_path_);
    file.stream() << text.str();
    file.Commit();
    return 0;
  }

 private:
  CLI::App* app_;
  std::string model_path_, output_path_;
  std::vector<std::string> joint_values_, joint_rates_;
  importers::ImportOptions options_;
};

}  // namespace

std::unique_ptr<Command> MakeImportCommand(CLI::App* parent) { return std::make_unique<ImportCommand>(parent); }

}  // namespace tether::cli
