#pragma once
// Loads a CORAL file with everything it imports. Import paths are relative
// to the importing file. A file reached twice (diamond imports) is parsed
// once; a cycle is an error at the import that closes it.
#include <map>
#include <memory>
#include <string>
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
};

class DiskFileProvider final : public FileProvider {
 public:
  std::string canonical(const std::string& path) const override;
  core::Result<std::string> read(const std::string& path) const override;
};

class MemoryFileProvider final : public FileProvider {
 public:
  void add(std::string path, std::string text) { files_[std::move(path)] = std::move(text); }
  std::string canonical(const std::string& path) const override;
  core::Result<std::string> read(const std::string& path) const override;

 private:
  std::map<std::string, std::string> files_;
};

struct LoadedFile {
  std::string path;  // as reached: the root as given, imports joined to their importer's folder
  ast::File tree;
};

// Every file of one load, the root first, then imports in the order met.
struct Load {
  std::vector<LoadedFile> files;
};

// Reads and parses root and its imports into sources; problems go to sink.
// A root that cannot be read is reported as FileUnreadable at no location.
Load load(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
          core::DiagnosticSink& sink);

}  // namespace strata::coral
