#pragma once
// From a checked load to a Program: each net becomes a petri::Net (places in
// declaration order, transitions in declaration order with their priority,
// wait -> Pre, signal -> Post) and an action table.
#include <optional>

#include "coral/checker.h"
#include "coral/loader.h"
#include "coral/program.h"
#include "core/diagnostic.h"

namespace strata::coral {

// Checks, then compiles when the check found no error. Warnings stay in sink.
std::optional<Program> compile(const Load& load, core::DiagnosticSink& sink, const CheckOptions& options = {});

// Loads root (with its imports) from provider, checks and compiles it.
std::optional<Program> compile_file(const std::string& root, const FileProvider& provider, core::SourceManager& sources,
                                    core::DiagnosticSink& sink, const CheckOptions& options = {});

}  // namespace strata::coral
