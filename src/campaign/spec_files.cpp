#include "campaign/spec_files.h"

#include <filesystem>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "core/file.h"
#include "vehicle/params.h"
#include "vehicle/scenario.h"

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;

// The largest world file read (a scenario of a few hundred bytes in practice).
constexpr std::size_t kMaxWorldBytes = 1u << 20;

struct NamedFile {
  const toml::node* key;  // where the spec names it, for errors
  std::string written;    // as the spec has it
  std::string resolved;   // relative to the spec's folder
};

// KEY = "FILE" in the spec's top level: nullopt when absent, or when it is
// not a non-empty string (said, as `what`).
std::optional<NamedFile> named_file(core::TomlErrors& errors, const toml::table& root, const char* key,
                                    const char* what, const Spec& spec) {
  const toml::node* n = root.get(key);
  if (n == nullptr) return std::nullopt;
  auto file = n->value<std::string>();
  if (!file || file->empty()) {
    errors.add(*n, fmt::format("'{}' must name {} (a string, relative to the spec)", key, what));
    return std::nullopt;
  }
  // The system's calls end a name at a NUL: "a.toml\u0000b" would open a.toml.
  if (file->find('\0') != std::string::npos) {
    errors.add(*n, fmt::format("'{}': a file name cannot hold a NUL character (\\u0000)", key));
    return std::nullopt;
  }
  return NamedFile{n, *file, (fs::path(spec.path).parent_path() / *file).lexically_normal().string()};
}

}  // namespace

void read_params(core::TomlErrors& errors, const toml::table& root, Spec& spec) {
  auto named = named_file(errors, root, "params", "a vehicle parameter file", spec);
  if (!named) return;
  auto params = vehicle::load_params(named->resolved);
  if (!params) {
    errors.add(*named->key, fmt::format("'params': {}", params.error().message));
    return;
  }
  spec.params = named->written;
  spec.params_resolved = named->resolved;
  spec.base_params = params.value();
}

void read_world(core::TomlErrors& errors, const toml::table& root, Spec& spec) {
  auto named = named_file(errors, root, "world", "a scenario file", spec);
  if (!named) return;
  const toml::node& n = *named->key;
  auto text = core::read_regular_file(named->resolved, kMaxWorldBytes);
  if (!text) {
    errors.add(n, fmt::format("'world': {}", text.error().message));
    return;
  }
  toml::table base;
  try {
    base = toml::parse(text.value(), named->resolved);
  } catch (const toml::parse_error& e) {
    errors.add(n, fmt::format("'world': {}:{}:{}: {}", named->resolved, e.source().begin.line, e.source().begin.column,
                              e.description()));
    return;
  }
  toml::table kept;
  for (auto&& [key, node] : base) {
    const std::string_view k = key.str();
    if (k == "world" || k == "seabed" || k == "vehicle") {
      kept.insert(key, node);
    } else if (k != "seed" && k != "description") {
      errors.add(n, fmt::format("'world': {} has '{}': a world file gives [world], [seabed] and [vehicle] "
                                "(the campaign gives each case its seed and its faults)",
                                named->written, k));
      return;
    }
  }
  // Checked as the scenario it is, so that an error names the world file's
  // own line (world_toml below is toml++'s text, laid out anew); a seed it
  // has is checked, then replaced by each case's.
  if (auto checked = vehicle::parse_world_scenario(text.value(), named->resolved); !checked) {
    errors.add(n, fmt::format("'world': {}", checked.error().message));
    return;
  }
  std::ostringstream out;
  out << kept;
  spec.world = named->written;
  spec.world_toml = out.str();
}

}  // namespace strata::campaign
