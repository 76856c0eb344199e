#include "results_folder.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include "tether/dynamics/trajectory_csv.h"

namespace tether {
namespace {

namespace fs = std::filesystem;

std::string Header(const StudySpec& spec) {
  std::string header;
  for (const std::string& p : spec.pointers) header += p + ",";
  for (const std::string& m : spec.metrics) header += m + ",";
  return header + "status";
}

// Rows finished by an earlier, interrupted run: "INDEX,<line>" after a header line equal to ours.
std::map<int, std::string> FinishedRows(const std::string& partial, const std::string& header) {
  std::map<int, std::string> rows;
  std::ifstream in(partial);
  std::string line;
  if (!std::getline(in, line) || line != "index," + header) return rows;
  while (std::getline(in, line)) {
    const size_t comma = line.find(',');
    if (comma == std::string::npos) continue;
    rows[std::atoi(line.substr(0, comma).c_str())] = line.substr(comma + 1);
  }
  return rows;
}

StudyRow ParseLine(const StudySpec& spec, int index, const std::string& line) {
  StudyRow row;
  row.values = Combination(spec, index);
  std::stringstream cells(line);
  std::string cell;
  for (size_t k = 0; k < spec.pointers.size(); ++k) std::getline(cells, cell, ',');
  for (size_t m = 0; m < spec.metrics.size(); ++m) {
    std::getline(cells, cell, ',');
    row.metrics.push_back(cell == "nan" ? NAN : std::strtod(cell.c_str(), nullptr));
  }
  std::getline(cells, row.status);
  return row;
}

std::string PartialPath(const std::string& folder) { return (fs::path(folder) / "results.partial.csv").string(); }

}  // namespace

ResultsFolder::ResultsFolder(const StudySpec& spec, const std::string& folder, const StudyProgress& progress)
    : spec_(spec), folder_(folder), header_(Header(spec)), progress_(progress), lines_(RowCount(spec)) {
  fs::create_directories(folder);
  const std::map<int, std::string> finished = FinishedRows(PartialPath(folder), header_);
  for (const auto& [index, line] : finished) {
    if (index >= 0 && index < static_cast<int>(lines_.size()) && lines_[index].empty()) {
      lines_[index] = line;
      ++done_;
    }
  }
  resumed_ = done_;
  log_.open(PartialPath(folder), finished.empty() ? std::ios::trunc : std::ios::app);
  if (finished.empty()) log_ << "index," << header_ << "\n" << std::flush;
}

std::vector<int> ResultsFolder::Unfinished() const {
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(lines_.size()); ++i) {
    if (lines_[i].empty()) rows.push_back(i);
  }
  return rows;
}

void ResultsFolder::Record(const FinishedRow& row) {
  lines_.at(row.index) = row.line;
  log_ << row.index << "," << row.line << "\n" << std::flush;
  ++done_;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int total = static_cast<int>(lines_.size());
  progress_(done_, total, elapsed / (done_ - resumed_) * (total - done_));
}

std::vector<StudyRow> ResultsFolder::Finish() {
  log_.close();
  AtomicOutputFile out((fs::path(folder_) / "results.csv").string());
  out.stream() << header_ << "\n";
  for (const std::string& line : lines_) {
    if (line.empty()) throw std::logic_error("ResultsFolder::Finish: a row is unfinished");
    out.stream() << line << "\n";
  }
  out.Commit();
  fs::remove(PartialPath(folder_));
  std::vector<StudyRow> rows;
  for (int i = 0; i < static_cast<int>(lines_.size()); ++i) rows.push_back(ParseLine(spec_, i, lines_[i]));
  return rows;
}

}  // namespace tether
