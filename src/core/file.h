#pragma once
// Whole files in and out.
//
// Reading a whole input file that someone else may have made: only a
// regular file is read (a FIFO, a device or a folder is refused at once,
// never waited on), and only up to a size the caller sets. Every input file
// outside the studio is read through here (CORAL sources, PROLOG rules,
// PNML, TOML, mission logs, gnuplot's messages, the files a run hashes).
//
// Writing a whole output file so that no reader ever sees half of it and a
// failure never costs the old one: write_file_atomically(). Every file
// written complete at once goes through it (exports, reports, witnesses,
// man pages, plots, sonar frames, the studio's saves beneath its own
// confinement); streams that grow as a run goes (mission logs, results
// lines) do not.
#include <sys/types.h>

#include <cstddef>
#include <string>
#include <string_view>

#include "core/result.h"

namespace strata::core {

// The message for a file that cannot be opened, from its path and the
// system's reason (strerror): for callers whose wording is known to their
// users ("cannot open 'x': ..."). By default: "cannot read 'x': reason".
using CannotOpenText = std::string (*)(const std::string& path, const char* reason);

// The bytes of the regular file at path, following links. Errors: Io when
// it cannot be opened or read, or is not a regular file; Overflow when it
// is larger than max_bytes (the message names the limit).
Result<std::string> read_regular_file(const std::string& path, std::size_t max_bytes,
                                      CannotOpenText cannot_open = nullptr);

// read_regular_file for a file that must be what its name says: when path
// ends in `suffix` (".coral"), the file opened must too, by the name it
// has once its links are resolved (what /proc/self/fd says of the open
// file), checked before a byte of it is read. Else ErrorCode::Io, naming
// where the link leads ("'x.coral' is a link to '/etc/passwd', which is not
// a .coral file; not read"), or saying that could not be told. A path that
// does not end in suffix is read as read_regular_file reads it.
Result<std::string> read_regular_file_as_named(const std::string& path, std::size_t max_bytes, std::string_view suffix,
                                               CannotOpenText cannot_open = nullptr);

struct WriteOptions {
  // The permissions of the file written, less the process's umask (as for
  // any file the process creates).
  mode_t mode = 0644;
  // When the target exists, the new file takes its permissions instead of
  // `mode` (an edited script stays executable).
  bool keep_existing_mode = false;
  // fsync the file before the rename and the folder after it, so that the
  // new file survives a crash. Off for files rewritten several times a
  // second (sonar frames), which must be whole for readers, not durable.
  bool durable = true;
};

// Replaces (or creates) the file at path with exactly `bytes`, atomically: a
// fresh temporary file in the same folder (a unique hidden name, created
// O_CREAT|O_EXCL|O_NOFOLLOW, so nothing planted at any name is written
// through), all bytes written, fsync, then rename(2) over path, and the
// folder synced (the syncs unless options.durable is false). A reader sees the old file or the new one, never a part.
//
// What is at path decides, looked at without following a link, before the
// temporary file is made and again just before the rename:
//  - nothing: the file is created;
//  - a regular file: it is replaced (a new inode: links to it elsewhere keep
//    the old bytes);
//  - a symbolic link: refused, whatever it points to; the link and its
//    target are left alone (a caller that means to follow a link resolves
//    it first, as the studio's sandbox does within its folder);
//  - a folder, a FIFO, a device or a socket: refused, never opened (so a
//    FIFO without a reader never blocks the writer).
// The folders on the way to path are followed as named: confining a write
// to a folder is the caller's business.
//
// Errors, always ErrorCode::Io, naming path and the reason ("cannot write
// 'p': No space left on device", "cannot write 'p': a symbolic link; not
// written through it"). On every failure the temporary file is removed and
// whatever was at path is as it was.
Result<void> write_file_atomically(const std::string& path, std::string_view bytes, WriteOptions options = {});

// The same for the entry `name` (a single file name, no '/') of the open
// folder dir_fd, which the caller keeps open; `shown` names the file in
// messages. For callers that have checked the folder they opened (the
// studio's sandbox).
Result<void> write_file_atomically_at(int dir_fd, const std::string& name, std::string_view bytes,
                                      const std::string& shown, WriteOptions options = {});

// An Io error for the system call that just failed: "what: strerror(errno)".
Error errno_error(const std::string& what);

}  // namespace strata::core
