// One way in for every input file tether reads (a scene, a study, a data file, a URDF or MJCF model): what is not a
// regular file is refused before it is opened (a folder would read as nothing and be reported as bad content; a
// device such as /dev/zero or a FIFO never ends), and so is a file larger than the reader's bound, with an
// InputError naming the file and what it was read as.
#pragma once

#include <cstdint>
#include <string>

namespace tether {

// Text files tether parses whole (scenes, studies, models) are at most this large.
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{256} << 20;  // 256 MiB

// Throws InputError ("PATH: cannot open the WHAT", "PATH: the WHAT is a folder, not a file", ...) unless `path`
// is a regular file (a link to one counts) of at most `limit` bytes.
void CheckInputFile(const std::string& path, const std::string& what, std::uintmax_t limit = kMaxTextFileBytes);

// The whole file, after CheckInputFile.
std::string ReadInputFile(const std::string& path, const std::string& what, std::uintmax_t limit = kMaxTextFileBytes);

}  // namespace tether
