#include "strategic/prolog_messages.h"

#include <map>

#include "core/file.h"

namespace strata::strategic {

bool is_error(const PrologMessage& message) { return core::default_severity(message.kind) == core::Severity::Error; }

void report_messages(std::span<const PrologMessage> messages, std::size_t max_bytes, core::SourceManager& sources,
                     core::DiagnosticSink& sink) {
  struct Added {
    core::FileId id;
    bool has_text;
  };
  std::map<std::string, Added> added;
  for (const auto& m : messages) {
    if (m.file.empty()) {  // no place: the printers say "strata: "
      sink.report(m.kind, {core::FileId(-1), 0, 0}, m.text);
      continue;
    }
    auto [at, fresh] = added.try_emplace(m.file, Added{0, false});
    if (fresh) {
      auto text = core::read_regular_file(m.file, max_bytes);
      at->second.has_text = text.ok();
      at->second.id = sources.add(m.file, text ? std::move(text).value() : std::string());
    }
    const Added& file = at->second;
    core::SourceSpan span{file.id, 0, 0};
    core::Precision precision = core::Precision::File;
    if (m.line > 0 && file.has_text) {
      span.offset = sources.offset_of(file.id, {m.line, m.column > 0 ? m.column : 1});
      precision = m.column > 0 ? core::Precision::Span : core::Precision::Line;
    }
    if (core::Diagnostic* d = sink.report(m.kind, span, m.text)) d->precision = precision;
  }
}

}  // namespace strata::strategic
