// `tether import MODEL.xml|MODEL.urdf [-o SCENE.json] [--joint NAME=VALUE ...] [--joint-velocity NAME=RATE ...]
//                [--fix BODY ...] [--merge-fixed] [--split-joints]`
// Writes a tether scene made from an MJCF or URDF model (importers/, docs/import.md) to SCENE.json (stdout
// without -o), and one warning per kind of thing the scene cannot carry on stderr.
#pragma once

#include <memory>

#include "command.h"

namespace tether::cli {

std::unique_ptr<Command> MakeImportCommand(CLI::App* parent);

}  // namespace tether::cli
