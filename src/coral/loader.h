#pragma once
// Loads a CORAL file with everything it imports. Import paths are relative
// to the importing file; `import NAME;` reads NAME.coral from the first
// folder of the library path that holds it (docs/library.md). A file
// reached twice (diamond imports) is parsed once; a cycle is an error at
// the import that closes it.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "coral/ast.h"
#include "core/diagnostic.h"
#include "core/result.h"
#include "core/source.h"

namespace strata::coral {

inline constexpr std::size_t kMaxImportDepth = 64;
inline constexpr std::size_t kMaxFiles = 1024;
inline constexpr std::size_t kMaxTotalSource = std::size_t{64} * 1024 * 1024;  // bytes, all files of a load

// Where source text comes from: the file system, or memory in tests and
// fuzzing (the seam that keeps those away from the disk).
class FileProvider {
 public:
  virtual ~FileProvider() = default;
  // A key naming the file uniquely (for cycle and duplicate detection).
  virtual std::string canonical(const std::string& path) const = 0;
  virtual core::Result<std::string> read(const std::string& path) const = 0;
  // Whether path names something (a file, or something that is not one:
  // reading it says what). The library path takes the first folder where
  // a module exists.
  virtual bool exists(const std::string& path) const { return static_cast<bool>(read(path)); }
};

class DiskFileProvider final : public FileProvider {
 public:
  std::string canonical(const std::string& path) const override;
  core::Result<std::string> read(const std::string& path) const override;
  bool exists(const std::string& path) const override;
};

class MemoryFileProvider final : public FileProvider {
 public:
  void add(std::string path, std::string text) { files_[std::move(path)] = std::move(text); }
  std::string canonical(const std::string& path) const override;
  core::Result<std::string> read(const std::string& path) const override;
  bool exists(const std::string& path) const override;

 private:
  std::map<std::string, std::string> files_;
};

// The folders Strata's phase library is searched in, for one language
// ("coral": NAME.coral; "prolog": NAME.pl), in order: each folder of the
// environment variable STRATA_LIBRARY (colon-separated; empty entries
// skipped), then Strata's own library: <prefix>/share/strata/library/LANG,
// found from the running executable (bin/../share/strata/library/LANG) when
// it is there, as for an installed strata; else the source tree's
// library/LANG, for a strata run from its build folder.
std::vector<std::string> library_dirs(std::string_view language);
// The same from given inputs (tests): env is STRATA_LIBRARY's value (null
// when unset), exe the running executable's path (empty when unknown).
std::vector<std::string> library_dirs(std::string_view language, const char* env, const std::filesystem::path& exe);

// Where `import NAME;` looks: NAME.coral in each folder, in order. Library
// modules are trusted Strata files read through `files`, not through the
// load's own provider (the studio reads them outside its folder; they are
// never written).
struct Library {
  std::vector<std::string> dirs;
  const FileProvider* files = nullptr;  // null: the disk
};

// The library of library_dirs("coral"), read from the disk.
Library standard_library();

struct LoadedFile {
  std::string path;  // as reached: the root as given, imports joined to their importer's folder
  ast::File tree;
  bool library = false;  // a module of the phase library (read-only), or a file it imports
};

// Every file of one load, the root first, then imports in the order met.
struct Load {
  std::vector<LoadedFile> files;
};

// Reads and parses root and its imports into sources; problems go to sink.
// A root that cannot be read is reported as FileUnreadable at no location.
// `import NAME;` is searched in standard_library().
Load load(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
          core::DiagnosticSink& sink);
// The same with `import NAME;` searched in `library`.
Load load(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
          core::DiagnosticSink& sink, const Library& library);

}  // namespace strata::coral
