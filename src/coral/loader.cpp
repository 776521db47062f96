#include "coral/loader.h"

#include <cstdlib>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "coral/lexer.h"
#include "core/file.h"
#include "coral/parser.h"

// The source tree's library/ (CMake sets it), for a strata run from its
// build folder.
#ifndef STRATA_LIBRARY_SOURCE_DIR
#define STRATA_LIBRARY_SOURCE_DIR ""
#endif

namespace strata::coral {
namespace fs = std::filesystem;

std::vector<std::string> library_dirs(std::string_view language, const char* env, const fs::path& exe) {
  std::vector<std::string> dirs;
  for (std::string_view rest = env ? env : ""; !rest.empty();) {
    const auto colon = rest.find(':');
    if (colon != 0) dirs.emplace_back(rest.substr(0, colon));
    rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
  }
  if (!exe.empty()) {
    const fs::path installed =
        (exe.parent_path() / ".." / "share" / "strata" / "library" / language).lexically_normal();
    std::error_code ec;
    if (fs::is_directory(installed, ec)) {
      dirs.push_back(installed.string());
      return dirs;
    }
  }
  if (*STRATA_LIBRARY_SOURCE_DIR) dirs.push_back((fs::path(STRATA_LIBRARY_SOURCE_DIR) / language).string());
  return dirs;
}

std::vector<std::string> library_dirs(std::string_view language) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return library_dirs(language, std::getenv("STRATA_LIBRARY"), ec ? fs::path() : exe);
}

Library standard_library() { return {library_dirs("coral"), nullptr}; }

std::string DiskFileProvider::canonical(const std::string& path) const {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(path, ec);
  return ec ? fs::path(path).lexically_normal().string() : p.string();
}

// A file named .coral must be one once its links are resolved: a link
// phases.coral -> ~/.ssh/id_rsa is not read (its lines would show in the
// syntax errors).
core::Result<std::string> DiskFileProvider::read(const std::string& path) const {
  auto text = core::read_regular_file_as_named(
      path, kMaxSourceSize, ".coral",
      [](const std::string& p, const char* reason) { return fmt::format("cannot open '{}': {}", p, reason); });
  if (!text && text.error().code == core::ErrorCode::Overflow) {
    // Too big to be a mission: the text's fault, not the disk's.
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("'{}' is over the limit of {} bytes", path, kMaxSourceSize));
  }
  return text;
}

bool DiskFileProvider::exists(const std::string& path) const {
  std::error_code ec;
  return fs::exists(path, ec);
}

std::string MemoryFileProvider::canonical(const std::string& path) const {
  return fs::path(path).lexically_normal().string();
}

core::Result<std::string> MemoryFileProvider::read(const std::string& path) const {
  auto it = files_.find(canonical(path));
  if (it == files_.end()) {
    return core::make_error(core::ErrorCode::Io, fmt::format("no file '{}'", path));
  }
  return it->second;
}

bool MemoryFileProvider::exists(const std::string& path) const { return files_.count(canonical(path)) > 0; }

namespace {

// How a file was reached: the provider that reads it, and for a module of
// the phase library (or a file it imports) the library folder it is in.
struct Reach {
  const FileProvider* files;
  std::string library_dir;  // empty: a mission's own file
};

bool lexically_inside(const std::string& dir, const std::string& path) {
  const fs::path rel = fs::path(path).lexically_relative(dir);
  return !rel.empty() && *rel.begin() != "..";
}

bool is_coral_file(std::string_view path) { return path.ends_with(".coral"); }

class Loader {
 public:
  Loader(const FileProvider& provider, const Library& library, core::SourceManager& sources, core::DiagnosticSink& sink)
      : provider_(provider), library_(library), sources_(sources), sink_(sink) {}

  void visit_root(const std::string& path) { visit(path, nullptr, {&provider_, {}}); }

  Load take() { return std::move(load_); }

 private:
  // Loads path (reached from `from`, or the root if from is null).
  void visit(const std::string& path, const ast::Import* from, const Reach& reach) {
    const FileProvider& files = *reach.files;
    std::string key = files.canonical(path);
    for (std::size_t i = 0; i < stack_.size(); ++i) {
      if (stack_[i] == key) {
        auto* d = sink_.report(core::DiagnosticKind::ImportCycle, from ? from->span : core::SourceSpan{},
                               fmt::format("import of '{}' makes a cycle", path));
        std::string chain;
        for (std::size_t j = i; j < stack_.size(); ++j) chain += shown_[j] + " -> ";
        core::add_note(d, fmt::format("the cycle is {}{}", chain, path));
        return;
      }
    }
    if (done_.count(key)) return;
    // An import reads CORAL files only: a mission's folder must not have
    // `strata check` show another file's lines in its syntax errors
    // (`import "/etc/passwd";`), which a run in CI would put in its log. A
    // link named .coral to a file that is not is refused where it is read
    // (DiskFileProvider::read). The root is the file the user named.
    if (from != nullptr && !is_coral_file(path)) {
      sink_.report(core::DiagnosticKind::FileUnreadable, from->span,
                   fmt::format("'{}' is not a CORAL file (.coral): an import reads only CORAL files, and this one is "
                               "not read",
                               path));
      return;
    }
    if (stack_.size() >= kMaxImportDepth) {
      sink_.report(core::DiagnosticKind::ImportTooDeep, from ? from->span : core::SourceSpan{},
                   fmt::format("imports are nested more than {} deep", kMaxImportDepth));
      return;
    }
    if (load_.files.size() >= kMaxFiles) {
      sink_.report(core::DiagnosticKind::ImportTooDeep, from ? from->span : core::SourceSpan{},
                   fmt::format("a mission may load at most {} files", kMaxFiles));
      return;
    }
    done_.insert(key);
    auto text = files.read(path);
    if (!text) {
      // An unreadable root has no location: the span's file is out of range.
      core::SourceSpan where = from ? from->span : core::SourceSpan{core::FileId(-1), 0, 0};
      sink_.report(text.error().code == core::ErrorCode::InvalidInput ? core::DiagnosticKind::FileTooLarge
                                                                      : core::DiagnosticKind::FileUnreadable,
                   where, text.error().message);
      return;
    }
    total_bytes_ += text.value().size();
    if (total_bytes_ > kMaxTotalSource) {
      sink_.report(core::DiagnosticKind::FileTooLarge, from ? from->span : core::SourceSpan{core::FileId(-1), 0, 0},
                   fmt::format("the files of this load pass {} bytes in all", kMaxTotalSource));
      return;
    }
    core::FileId id = sources_.add(path, std::move(text).value());
    std::size_t index = load_.files.size();
    load_.files.push_back({path, parse(sources_, id, sink_), !reach.library_dir.empty()});
    stack_.push_back(key);
    shown_.push_back(path);
    // Copy: visiting appends to load_.files, which may move the tree.
    std::vector<ast::Import> imports = load_.files[index].tree.imports;
    fs::path dir = fs::path(path).parent_path();
    for (const auto& imp : imports) {
      if (imp.by_name) {
        visit_module(imp);
        continue;
      }
      std::string joined = (dir / imp.path).lexically_normal().string();
      if (!reach.library_dir.empty() && !lexically_inside(reach.library_dir, joined)) {
        sink_.report(core::DiagnosticKind::FileUnreadable, imp.span,
                     fmt::format("'{}' is outside the library folder {}: a library module imports only its own "
                                 "folder's files, or other modules by name",
                                 joined, reach.library_dir));
        continue;
      }
      visit(joined, &imp, reach);
    }
    stack_.pop_back();
    shown_.pop_back();
  }

  // `import NAME;`: NAME.coral from the first library folder that has it.
  void visit_module(const ast::Import& imp) {
    const FileProvider& files = library_.files ? *library_.files : disk_;
    const std::string file = imp.path + ".coral";
    for (const auto& dir : library_.dirs) {
      const std::string candidate = (fs::path(dir) / file).lexically_normal().string();
      if (files.exists(candidate)) {
        visit(candidate, &imp, {&files, fs::path(dir).lexically_normal().string()});
        return;
      }
    }
    std::string looked;
    for (const auto& dir : library_.dirs) looked += fmt::format("{}{}", looked.empty() ? "" : ", ", dir);
    auto* d = sink_.report(core::DiagnosticKind::UnknownModule, imp.span,
                           fmt::format("no library module '{}': {} is in none of the library's folders ({})", imp.path,
                                       file, looked.empty() ? "there are none" : looked));
    core::add_note(d, "STRATA_LIBRARY adds folders (colon-separated) before Strata's own library (docs/library.md)");
  }

  const FileProvider& provider_;
  const Library& library_;
  DiskFileProvider disk_;  // reads the library when library_.files is null
  core::SourceManager& sources_;
  core::DiagnosticSink& sink_;
  std::vector<std::string> stack_;  // canonical keys of the files being loaded
  std::vector<std::string> shown_;  // the same files, as reached (for messages)
  std::set<std::string> done_;
  std::size_t total_bytes_ = 0;
  Load load_;
};

}  // namespace

Load load(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
          core::DiagnosticSink& sink, const Library& library) {
  Loader loader(provider, library, sources, sink);
  loader.visit_root(root);
  return loader.take();
}

Load load(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
          core::DiagnosticSink& sink) {
  return load(root, provider, sources, sink, standard_library());
}

}  // namespace strata::coral
