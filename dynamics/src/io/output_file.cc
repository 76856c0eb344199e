#include "tether/dynamics/io/output_file.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

namespace fs = std::filesystem;

// The file a write to `path` lands in: `path` itself, or the end of its chain of links.
std::string Target(const std::string& path) {
  std::error_code error;
  if (!fs::is_symlink(path, error)) return path;
  const fs::path target = fs::canonical(path, error);
  if (error) throw InputError(path + ": a symbolic link to nothing (" + error.message() + "); cannot write through it");
  return target.string();
}

}  // namespace

AtomicOutputFile::AtomicOutputFile(const std::string& path) : path_(path), target_(Target(path)) {
  std::error_code error;
  const fs::file_status status = fs::status(target_, error);
  if (fs::is_directory(status)) throw InputError(path + ": is a folder, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {  // a device or a FIFO: written through
    stream_.open(target_, std::ios::binary);
  } else {
    temporary_ = target_ + ".partial." + std::to_string(::getpid());
    registered_ = std::make_unique<TemporaryPath>(temporary_);
    stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  }
  if (!stream_) {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
    throw InputError(path + ": cannot write the output file here");
  }
}

AtomicOutputFile::~AtomicOutputFile() {
  if (!committed_ && !temporary_.empty()) {
    stream_.close();
    std::remove(temporary_.c_str());
  }
}

void AtomicOutputFile::Commit() {
  stream_.flush();
  stream_.close();
  if (!stream_) {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
    throw OutputError(path_ + ": writing the output file failed (is the disk full?)");
  }
  if (!temporary_.empty() && std::rename(temporary_.c_str(), target_.c_str()) != 0) {
    std::remove(temporary_.c_str());
    throw OutputError(path_ + ": cannot complete the output file (renaming the temporary file failed)");
  }
  committed_ = true;
}

void CheckOutputPath(const std::string& path, const std::vector<std::string>& inputs, const std::string& flag) {
  std::error_code error;
  for (const std::string& input : inputs) {
    if (fs::equivalent(path, input, error)) {
      throw InputError(flag + ": '" + path + "' is an input of this run (" + input + "); write the output elsewhere");
    }
  }
  const std::string target = Target(path);
  if (fs::is_directory(target, error)) throw InputError(flag + ": '" + path + "' is a folder, not a file");
  if (fs::exists(target, error)) {
    if (::access(target.c_str(), W_OK) != 0) throw InputError(flag + ": '" + path + "' cannot be written");
  }
  fs::path folder = fs::path(target).parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, error)) throw InputError(flag + ": the folder of '" + path + "' does not exist");
  if (fs::is_regular_file(target, error) || !fs::exists(target, error)) {  // a temporary file goes beside it
    if (::access(folder.c_str(), W_OK) != 0) {
      throw InputError(flag + ": cannot write into the folder of '" + path + "'");
    }
  }
}

}  // namespace tether
