// Files a user names, checked before a byte is read.
//
// Only a regular file is read (a link is followed to what it names): a FIFO would block the
// read forever, and a link to /dev/zero or another device would be read until memory runs out.
// A size limit per kind of file bounds what one read can take. Both refusals are InputErrors
// that name the file and say what to do. docs/reliability.md gives each limit with its reason.
#pragma once

#include <cstdint>
#include <string>

namespace cellmetry {

// A YAML file: a job, a robot config, a mapping, recording.yaml. These are a few KB.
inline constexpr std::uintmax_t kMaxYamlBytes = std::uintmax_t{4} << 20;  // 4 MB
// A table: samples.csv, observations.csv, images.csv, a table to import, a detection log.
inline constexpr std::uintmax_t kMaxTableBytes = std::uintmax_t{256} << 20;  // 256 MB

// Raises InputError unless `path` is a regular file of at most `max_bytes`. `missing_hint` is
// the advice when nothing is there (a reader knows where the path came from).
void RequireRegularFile(const std::string& path, std::uintmax_t max_bytes,
                        const std::string& missing_hint);

// The whole of `path` once RequireRegularFile has passed; binary, no newline translation.
std::string ReadRegularFile(const std::string& path, std::uintmax_t max_bytes,
                            const std::string& missing_hint);

}  // namespace cellmetry
