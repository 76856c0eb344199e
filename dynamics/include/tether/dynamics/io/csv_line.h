// One line of a CSV file tether writes or reads (trajectories, events, data, study results; RFC 4180, without
// line breaks inside cells): a cell holding a comma, a double quote or a line break is written in double quotes
// with its quotes doubled (line breaks become spaces), and read back the same way. Python's csv module and pandas
// read these lines as written.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace tether {

std::string CsvCell(const std::string& text);

// The cells of `line`, or nothing when it is not well formed (an unclosed quote, text after a closing quote).
std::optional<std::vector<std::string>> SplitCsvLine(const std::string& line);

}  // namespace tether
