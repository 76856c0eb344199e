#include "csv_columns.h"

#include <vector>

#include "test_files.h"

namespace tether::testing {

std::string WithoutColumn(const std::string& csv, const std::string& drop) {
  const std::vector<std::string> lines = Lines(csv);
  if (lines.empty()) return "";
  const std::vector<std::string> header = CsvCells(lines[0]);
  std::string out;
  for (const std::string& line : lines) {
    const std::vector<std::string> cells = CsvCells(line);
    for (size_t k = 0; k < cells.size(); ++k) {
      if (k < header.size() && header[k] == drop) continue;
      out += cells[k] + ";";
    }
    out += "\n";
  }
  return out;
}

}  // namespace tether::testing
