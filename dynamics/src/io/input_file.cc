#include "tether/dynamics/io/input_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tether/dynamics/model/errors.h"

namespace tether {

namespace fs = std::filesystem;

void CheckInputFile(const std::string& path, const std::string& what, std::uintmax_t limit) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) throw InputError(path + ": cannot open the " + what + " (no such file)");
  if (fs::is_directory(status)) throw InputError(path + ": the " + what + " is a folder, not a file");
  if (!fs::is_regular_file(status)) {
    throw InputError(path + ": the " + what +
                     " is not a regular file (a device, a pipe or a socket cannot be read "
                     "as one)");
  }
  const std::uintmax_t bytes = fs::file_size(path, error);
  if (!error && bytes > limit) {
    throw InputError(path + ": the " + what + " has " + std::to_string(bytes) + " bytes, more than tether reads (" +
                     std::to_string(limit) + ")");
  }
}

std::string ReadInputFile(const std::string& path, const std::string& what, std::uintmax_t limit) {
  CheckInputFile(path, what, limit);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the " + what);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace tether
