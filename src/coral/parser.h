#pragma once
// Recursive-descent parser for one CORAL file (grammar: docs/language.md).
// On a syntax error it reports once, skips to the next `;`, `}` or
// declaration keyword and goes on; errors met while skipping are not
// reported, so one mistake gives one diagnostic.
#include "coral/ast.h"
#include "core/diagnostic.h"
#include "core/source.h"

namespace strata::coral {

// The most arguments a call may be given (a primitive's or a PHASE's) and the
// most parameters a net may declare; past it, TooManyArguments.
inline constexpr std::size_t kMaxArguments = 256;

// Parses the file `id` of sources. Never fails: problems go to sink and the
// tree holds what could be recovered.
ast::File parse(const core::SourceManager& sources, core::FileId id, core::DiagnosticSink& sink);

}  // namespace strata::coral
