#include "tether/dynamics/trajectory_csv.h"

#include <unistd.h>

#include <charconv>
#include <cstdio>

#include "tether/dynamics/errors.h"

namespace tether {

std::vector<std::string> TrajectoryColumns(const Model<double>& model) {
  static const char* kAxes[3] = {"x", "y", "z"};
  std::vector<std::string> columns = {"t"};
  for (const Body<double>& body : model.bodies) {
    const bool rigid = body.kind == BodyKind::kRigid;
    for (int k = 0; k < model.dimension; ++k) columns.push_back(body.name + "." + kAxes[k]);
    if (rigid) columns.push_back(body.name + ".angle");
    for (int k = 0; k < model.dimension; ++k) columns.push_back(body.name + ".v" + kAxes[k]);
    if (rigid) columns.push_back(body.name + ".omega");
  }
  columns.push_back("constraint_error");
  columns.push_back("energy");
  return columns;
}

TrajectoryCsvWriter::TrajectoryCsvWriter(const Model<double>& model, std::ostream* out) : model_(model), out_(out) {
  const std::vector<std::string> columns = TrajectoryColumns(model);
  for (size_t i = 0; i < columns.size(); ++i) *out_ << (i ? "," : "") << columns[i];
  *out_ << '\n';
}

void TrajectoryCsvWriter::Write(const Sample<double>& s) {
  char number[32];
  line_.clear();
  auto put = [&](double x) {
    const std::to_chars_result end = std::to_chars(number, number + sizeof number, x);
    if (!line_.empty()) line_ += ',';
    line_.append(number, end.ptr);
  };
  put(s.t);
  for (const Body<double>& body : model_.bodies) {
    for (int k = 0; k < body.size; ++k) put(s.q[body.offset + k]);
    for (int k = 0; k < body.size; ++k) put(s.v[body.offset + k]);
  }
  put(s.constraint_error);
  put(s.energy);
  line_ += '\n';
  *out_ << line_;
}

AtomicOutputFile::AtomicOutputFile(const std::string& path)
    : path_(path), temporary_(path + ".partial." + std::to_string(::getpid())) {
  stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!stream_) throw InputError(path + ": cannot write the output file here");
}

AtomicOutputFile::~AtomicOutputFile() {
  if (!committed_) {
    stream_.close();
    std::remove(temporary_.c_str());
  }
}

void AtomicOutputFile::Commit() {
  stream_.close();
  if (!stream_ || std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    std::remove(temporary_.c_str());
    throw InputError(path_ + ": cannot complete the output file");
  }
  committed_ = true;
}

}  // namespace tether
