#include "tether/dynamics/io/csv_line.h"

namespace tether {

std::string CsvCell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string cell = "\"";
  for (char c : text) {
    if (c == '"') {
      cell += "\"\"";
    } else {
      cell += c == '\n' || c == '\r' ? ' ' : c;
    }
  }
  return cell + "\"";
}

std::optional<std::vector<std::string>> SplitCsvLine(const std::string& line) {
  std::vector<std::string> cells(1);
  for (size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (c == ',') {
      cells.emplace_back();
    } else if (c == '"' && cells.back().empty()) {  // a quoted cell, up to its closing quote
      for (++k;; ++k) {
        if (k >= line.size()) return std::nullopt;
        if (line[k] == '"') {
          if (k + 1 < line.size() && line[k + 1] == '"') {
            cells.back() += '"';
            ++k;
          } else {
            break;
          }
        } else {
          cells.back() += line[k];
        }
      }
      if (k + 1 < line.size() && line[k + 1] != ',') return std::nullopt;
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

}  // namespace tether
