#pragma once
// The campaign's folder (--out DIR): results.jsonl, report.json,
// report.html, logs/case-I.jsonl and scenarios/case-I.toml. Nothing is
// written through a symbolic link: DIR itself must not be one, results.jsonl
// is opened with O_NOFOLLOW, and every other file is written whole by
// core::write_file_atomically (which refuses a link at its name).
#include <cstddef>
#include <cstdio>
#include <sys/types.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/result.h"

namespace strata::campaign {

// The largest results.jsonl or report.json read back (--merge, --compare).
inline constexpr std::size_t kMaxResultsBytes = std::size_t{1} << 30;

// Writes all of text to fd (a file, or a worker's pipe), through EINTR and
// short writes; false on an error (errno says which). A pipe whose reader
// is gone is an error (EPIPE), never a SIGPIPE.
bool write_all_fd(int fd, const std::string& text);

// Creates DIR with logs/ and scenarios/ in it. An existing DIR must be a
// folder (not a link) that is empty or holds an earlier campaign (a
// results.jsonl): that campaign's files are removed first, nothing else.
core::Result<void> prepare_out_dir(const std::string& dir);

// A folder to write into: made if missing; an existing one must be a real
// folder, not a link to one (Io error otherwise).
core::Result<void> make_real_dir(const std::string& path);

// Writes text to DIR/name whole and atomically (core::write_file_atomically:
// a link, a folder or a FIFO at the name is refused), with permissions mode
// less the umask; Io error on failure.
core::Result<void> write_out_file(const std::string& dir, const std::string& name, const std::string& text,
                                  mode_t mode = 0644);

// results.jsonl, a line per case as each arrives, flushed at once so that
// whatever ends the campaign keeps every finished case.
class ResultsFile {
 public:
  static core::Result<ResultsFile> create(const std::string& dir);
  ResultsFile(ResultsFile&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  ResultsFile& operator=(ResultsFile&&) = delete;
  ~ResultsFile();

  core::Result<void> append(const nlohmann::ordered_json& line);

 private:
  explicit ResultsFile(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace strata::campaign
