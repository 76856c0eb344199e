#include "flags.h"

#include <filesystem>
#include <system_error>

#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/model/errors.h"

namespace tether::cli {

void CheckOutputs(const std::vector<OutputFlag>& outputs, const std::vector<std::string>& inputs) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const OutputFlag& out = outputs[k];
    if (out.path.empty()) continue;
    if (out.figure) {
      const std::string extension = std::filesystem::path(out.path).extension().string();
      if (extension != ".png" && extension != ".svg") {
        throw InputError(out.flag + ": '" + out.path + "' must end in .png or .svg");
      }
    }
    CheckOutputPath(out.path, inputs, out.flag);
    for (size_t j = 0; j < k; ++j) {
      std::error_code error;
      if (!outputs[j].path.empty() && std::filesystem::weakly_canonical(out.path, error) ==
                                          std::filesystem::weakly_canonical(outputs[j].path, error)) {
        throw InputError(out.flag + ": '" + out.path + "' is also the output of " + outputs[j].flag);
      }
    }
  }
}

}  // namespace tether::cli
