#pragma once
// The studio's files: every path a request names is relative to one root
// folder, and must stay inside it. Refused (Error::InvalidInput, for a 403):
// an empty or absolute path, a backslash or NUL, a `..` component, and a
// path whose real location (symbolic links followed, for a file being
// written: its folder's) lies outside the root.
//
// The folder may be a hostile repository (issue 17): links planted at a
// file's name, at a temporary name, or in an import. Every byte the studio
// reads or writes for the folder goes through read() and write(), which
// check what they actually open, not only the name they were given.
//
// Threads: immutable after construction; every member is safe from any
// thread. write() does not serialise writers: the server does.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace strata::studio {

class Sandbox {
 public:
  static constexpr std::size_t kMaxReadBytes = 64u << 20;

  // Precondition: root exists and is a folder.
  explicit Sandbox(const std::filesystem::path& root);

  const std::filesystem::path& root() const { return root_; }
  // The real path of `relative`. For reading it must exist; for writing its
  // folder must exist inside the root (the file itself may not exist yet).
  core::Result<std::filesystem::path> resolve(std::string_view relative, bool for_write = false) const;
  // The bytes of a file inside the root (at most max_bytes). InvalidInput
  // (403): it leaves the root (checked lexically first, so a path outside
  // is never opened), is a link out, or is not a regular file; Io (404): it
  // is not there; Overflow: over max_bytes. The file is opened without
  // following a final link, then where the open file really is is checked
  // again before a byte is read.
  core::Result<std::string> read(std::string_view relative, std::size_t max_bytes = kMaxReadBytes) const;
  // The same for an absolute path or one relative to the process (imports,
  // joined to their importer's folder by the loader).
  core::Result<std::string> read_path(const std::filesystem::path& path, std::size_t max_bytes = kMaxReadBytes) const;
  // Replaces (or creates) a file inside the root with `bytes`, atomically,
  // by core::write_file_atomically_at in the folder opened and checked: a
  // fresh temporary file beside it (O_CREAT|O_EXCL|O_NOFOLLOW, a unique
  // name, so a link planted at any name is never written through), fsync,
  // then renamed over the target; an existing file keeps its permissions. The target, when it exists, must be a
  // regular file inside the root; a link at it is followed only when it
  // resolves inside (the file it points to is replaced). InvalidInput (403)
  // for every way out; Internal (500) when the disk refuses.
  core::Result<void> write(std::string_view relative, std::string_view bytes) const;
  // Creates a new, empty file `name` in the folder `folder` (relative; ""
  // is the root) and returns its open descriptor, for writing; the caller
  // closes it. The folder is created when missing (its parent must exist
  // inside the root). Nothing is followed: the parent and the folder are
  // opened O_NOFOLLOW and checked inside the root once open, the file is
  // created O_CREAT|O_EXCL|O_NOFOLLOW (a name already there, a link
  // included, is Overflow: pick another name). InvalidInput (403) for every
  // way out.
  core::Result<int> create_new(std::string_view folder, std::string_view name) const;
  // Removes `folder`/`name` when it is an empty regular file (a log that
  // was never written), without following any link.
  core::Result<void> remove_empty(std::string_view folder, std::string_view name) const;
  // Whether `path` (absolute, or relative to the process) names a place
  // inside the root before any link is resolved: nothing is looked at.
  bool lexically_inside(const std::filesystem::path& path) const;
  // `path` (inside the root) as a relative path with '/' separators.
  std::string relative(const std::filesystem::path& path) const;
  // Every regular file under the root with one of these extensions, as
  // relative paths, sorted; links that leave the root are not followed, and
  // folders named build, node_modules or starting with '.' are skipped.
  // Names that are not UTF-8 are left out, and counted in *unnamed.
  std::vector<std::string> list(const std::vector<std::string>& extensions, std::size_t* unnamed = nullptr) const;

 private:
  bool inside(const std::filesystem::path& real) const;
  // Opens `real` (a canonical path found inside) and reads it, checking the
  // open file itself; `shown` names it in messages.
  core::Result<std::string> read_real(const std::filesystem::path& real, std::string_view shown,
                                      std::size_t max_bytes) const;
  std::filesystem::path root_;  // canonical
};

}  // namespace strata::studio
