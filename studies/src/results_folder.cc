#include "results_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "tether/dynamics/io/csv_line.h"
#include "tether/dynamics/io/output_file.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFingerprintPrefix = "# tether study ";

std::string Header(const StudySpec& spec) {
  std::string header;
  for (const std::string& p : spec.pointers) header += CsvCell(p) + ",";
  for (const std::string& m : spec.metrics) header += m + ",";
  return header + "status";
}

// FNV-1a, 64 bits, over a file's bytes (a missing file hashes as its name).
void HashFile(const std::string& path, std::uint64_t* hash) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes = in ? std::string() : path;
  char buffer[1 << 16];
  auto mix = [hash](const char* data, size_t size) {
    for (size_t k = 0; k < size; ++k) *hash = (*hash ^ static_cast<unsigned char>(data[k])) * 1099511628211ull;
  };
  mix(bytes.data(), bytes.size());
  while (in) {
    in.read(buffer, sizeof buffer);
    mix(buffer, static_cast<size_t>(in.gcount()));
  }
  mix("\0", 1);  // a boundary between files
}

}  // namespace

std::string StudyFingerprint(const StudySpec& spec) {
  std::uint64_t hash = 14695981039346656037ull;
  HashFile(spec.path, &hash);
  for (const std::string& scene : spec.scene_paths) HashFile(scene, &hash);
  HashFile("/proc/self/exe", &hash);
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The whole lines of `text` (a last line without its line end is not whole).
std::vector<std::string> WholeLines(const std::string& text) {
  std::vector<std::string> lines;
  for (size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos; start = end + 1) {
    lines.push_back(text.substr(start, end - start));
  }
  return lines;
}

StudyRow ParseLine(const StudySpec& spec, int index, const std::string& line) {
  StudyRow row;
  row.values = Combination(spec, index);
  const std::vector<std::string> cells = SplitCsvLine(line).value();
  for (size_t m = 0; m < spec.metrics.size(); ++m) {
    const std::string& cell = cells[spec.pointers.size() + m];
    row.metrics.push_back(cell == "nan" ? NAN : std::strtod(cell.c_str(), nullptr));
  }
  row.status = cells.back();
  return row;
}

std::string PartialPath(const std::string& folder) { return (fs::path(folder) / "results.partial.csv").string(); }
std::string ResultsPath(const std::string& folder) { return (fs::path(folder) / "results.csv").string(); }
std::string FingerprintPath(const std::string& folder) {
  return (fs::path(folder) / "results.fingerprint").string();
}

}  // namespace

FolderLock::FolderLock(const std::string& folder) {
  std::error_code error;
  if (fs::exists(folder) && !fs::is_directory(folder)) {
    throw InputError("--out: '" + folder + "' is a file, not a folder");
  }
  fs::create_directories(folder, error);
  if (!fs::is_directory(folder)) throw InputError("--out: cannot make the folder '" + folder + "'");
  const std::string lock = (fs::path(folder) / ".lock").string();
  descriptor_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor_ < 0) throw InputError("--out: cannot write into the folder '" + folder + "'");
  if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0) {
    ::close(descriptor_);
    throw InputError("--out: another tether study is writing into '" + folder +
                     "' now; wait for it, or choose another folder");
  }
}

FolderLock::~FolderLock() { ::close(descriptor_); }

ResultsFolder::ResultsFolder(const StudySpec& spec, const std::string& folder, bool restart,
                             const StudyProgress& progress)
    : spec_(spec), folder_(folder), lock_(folder), header_(Header(spec)), fingerprint_(StudyFingerprint(spec)),
      progress_(progress), lines_(RowCount(spec)) {
  std::error_code error;
  for (int i = 0; i < total(); ++i) {
    cost_.push_back(RowCost(spec, i));
    cost_total_ += cost_.back();
  }
  const bool ours = ReadText(FingerprintPath(folder)) == fingerprint_ + "\n";
  if (!restart && !ours && fs::exists(ResultsPath(folder))) {
    throw InputError("--out: " + ResultsPath(folder) +
                     " holds the results of another study (its study file, scenes "
                     "or tether binary differ from this one's, or it has no fingerprint: results committed to a "
                     "repository, say); pass --restart to replace them, or choose another folder");
  }
  if (!restart && ours && fs::exists(ResultsPath(folder))) {
    done_already_ = true;
    const std::vector<std::string> lines = WholeLines(ReadText(ResultsPath(folder)));
    const size_t cells = spec.pointers.size() + spec.metrics.size() + 1;
    bool whole = lines.size() == lines_.size() + 1 && lines[0] == header_;
    for (size_t i = 1; whole && i < lines.size(); ++i) {
      const std::optional<std::vector<std::string>> split = SplitCsvLine(lines[i]);
      whole = split && split->size() == cells;
    }
    if (whole) {
      for (size_t i = 0; i < lines_.size(); ++i) lines_[i] = lines[i + 1];
      done_ = total();
      return;
    }
    done_already_ = false;  // results.csv was edited since: compute it again
  }
  fs::remove(FingerprintPath(folder), error);
  TakeUpPartial(restart);
}

void ResultsFolder::TakeUpPartial(bool restart) {
  const std::string partial = PartialPath(folder_);
  if (fs::exists(partial) && !restart) {
    const std::vector<std::string> lines = WholeLines(ReadText(partial));
    if (lines.size() < 2 || lines[0] != kFingerprintPrefix + fingerprint_ || lines[1] != "index," + header_) {
      throw InputError("--out: " + partial + " holds the partial results of another study (its study file, "
                       "scenes or tether binary have changed since); pass --restart to discard them, or choose "
                       "another folder");
    }
    const size_t cells = spec_.pointers.size() + spec_.metrics.size() + 2;  // index, values, metrics, status
    for (size_t k = 2; k < lines.size(); ++k) {
      const std::optional<std::vector<std::string>> split = SplitCsvLine(lines[k]);
      if (!split || split->size() != cells) continue;  // torn: the row runs again
      char* end = nullptr;
      const long index = std::strtol((*split)[0].c_str(), &end, 10);
      if (end == (*split)[0].c_str() || *end != '\0' || index < 0 || index >= total() || !lines_[index].empty()) {
        continue;
      }
      lines_[index] = lines[k].substr((*split)[0].size() + 1);
      ++done_;
      cost_resumed_ += cost_[index];
    }
  }
  cost_done_ = cost_resumed_;
  WritePartial();  // whole lines only, so that appending starts on a fresh line
  log_.open(partial, std::ios::app);
}

void ResultsFolder::WritePartial() {
  AtomicOutputFile out(PartialPath(folder_));
  out.stream() << kFingerprintPrefix << fingerprint_ << "\nindex," << header_ << "\n";
  for (size_t i = 0; i < lines_.size(); ++i) {
    if (!lines_[i].empty()) out.stream() << i << "," << lines_[i] << "\n";
  }
  out.Commit();
}

std::vector<int> ResultsFolder::Unfinished() const {
  std::vector<int> rows;
  for (int i = 0; i < total(); ++i) {
    if (lines_[i].empty()) rows.push_back(i);
  }
  return rows;
}

void ResultsFolder::Record(const FinishedRow& row) {
  lines_.at(row.index) = row.line;
  log_ << row.index << "," << row.line << "\n" << std::flush;
  if (!log_) throw OutputError(PartialPath(folder_) + ": writing the partial results failed (is the disk full?)");
  ++done_;
  cost_done_ += cost_[row.index];
  // the time left in proportion to the expected cost left (rows differ by their step counts)
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed / std::max(cost_done_ - cost_resumed_, 1e-300);
  progress_(done_, total(), rate * (cost_total_ - cost_done_));
}

std::vector<StudyRow> ResultsFolder::Finish() {
  if (!done_already_) {
    log_.close();
    AtomicOutputFile out(ResultsPath(folder_));
    out.stream() << header_ << "\n";
    for (const std::string& line : lines_) {
      if (line.empty()) throw std::logic_error("ResultsFolder::Finish: a row is unfinished");
      out.stream() << line << "\n";
    }
    out.Commit();
    AtomicOutputFile fingerprint(FingerprintPath(folder_));
    fingerprint.stream() << fingerprint_ << "\n";
    fingerprint.Commit();
    fs::remove(PartialPath(folder_));
  }
  std::vector<StudyRow> rows;
  for (int i = 0; i < total(); ++i) rows.push_back(ParseLine(spec_, i, lines_[i]));
  return rows;
}

}  // namespace tether
