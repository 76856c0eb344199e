#include "tether/importers/import_model.h"

#include <string>

#include "tether/dynamics/model/errors.h"

namespace tether::importers {
namespace {

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

}  // namespace

ImportedScene ImportModel(const std::string& path, const ImportOptions& options) {
  if (EndsWith(path, ".xml")) return SceneFromTree(ReadMjcf(path), options, path);
  if (EndsWith(path, ".urdf")) return SceneFromTree(ReadUrdf(path), options, path);
  throw InputError(path + ": unknown model format: the file's name must end in .xml (MJCF, MuJoCo) or .urdf (URDF)");
}

}  // namespace tether::importers
