#include "tether/dynamics/trajectory_csv.h"

#include <unistd.h>

#include <charconv>
#include <cstdio>

#include "tether/dynamics/errors.h"

namespace tether {

TrajectoryCsvWriter::TrajectoryCsvWriter(const Model<double>& model, std::ostream* out)
    : model_(model), columns_(TrajectoryColumns(model)), out_(out) {
  for (size_t i = 0; i < columns_.size(); ++i) *out_ << (i ? "," : "") << columns_[i].name;
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
  for (const TrajectoryColumn& column : columns_) put(ColumnValue(model_, column, s));
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
