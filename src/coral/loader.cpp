#include "coral/loader.h"

#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "coral/lexer.h"
#include "core/file.h"
#include "coral/parser.h"

namespace strata::coral {
namespace fs = std::filesystem;

std::string DiskFileProvider::canonical(const std::string& path) const {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(path, ec);
  return ec ? fs::path(path).lexically_normal().string() : p.string();
}

core::Result<std::string> DiskFileProvider::read(const std::string& path) const {
  auto text = core::read_regular_file(path, kMaxSourceSize, [](const std::string& p, const char* reason) {
    return fmt::format("cannot open '{}': {}", p, reason);
  });
  if (!text && text.error().code == core::ErrorCode::Overflow) {
    // Too big to be a mission: the text's fault, not the disk's.
    return core::make_error(core::ErrorCode::InvalidInput,
                            fmt::format("'{}' is over the limit of {} bytes", path, kMaxSourceSize));
  }
  return text;
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

namespace {

class Loader {
 public:
  Loader(const FileProvider& provider, core::SourceManager& sources, core::DiagnosticSink& sink)
      : provider_(provider), sources_(sources), sink_(sink) {}

  // Loads path (reached from `from`, or the root if from is null).
  void visit(const std::string& path, const ast::Import* from) {
    std::string key = provider_.canonical(path);
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
    auto text = provider_.read(path);
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
    load_.files.push_back({path, parse(sources_, id, sink_)});
    stack_.push_back(key);
    shown_.push_back(path);
    // Copy: visiting appends to load_.files, which may move the tree.
    std::vector<ast::Import> imports = load_.files[index].tree.imports;
    fs::path dir = fs::path(path).parent_path();
    for (const auto& imp : imports) {
      visit((dir / imp.path).lexically_normal().string(), &imp);
    }
    stack_.pop_back();
    shown_.pop_back();
  }

  Load take() { return std::move(load_); }

 private:
  const FileProvider& provider_;
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
          core::DiagnosticSink& sink) {
  Loader loader(provider, sources, sink);
  loader.visit(root, nullptr);
  return loader.take();
}

}  // namespace strata::coral
