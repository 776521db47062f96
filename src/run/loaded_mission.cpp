#include "run/loaded_mission.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>

#include <fmt/format.h>

#include "core/mission_language.h"
#include "core/file.h"
#include "coral/verify_report.h"
#include "run/bound_options.h"
#include "run/coral_load.h"
#include "run/inputs.h"
#include "run/scenario_folder.h"
#include "tactical/execution_level.h"
#include "tactical/sha256.h"

namespace strata::run {
namespace {

namespace fs = std::filesystem;

constexpr const char* kVersion = "0.1.0";

std::string sha256_or_empty(const RunOptions& o, const std::string& path) {
  if (o.read_file) {
    auto bytes = o.read_file(path);
    return bytes ? tactical::sha256_hex(bytes.value()) : std::string();
  }
  auto r = tactical::sha256_file(path);
  return r ? r.value() : std::string();
}

// The mission and its imports read through RunOptions::read_file. Names are
// compared lexically (nothing on disk is looked at but through the reader).
class ReaderFileProvider final : public coral::FileProvider {
 public:
  explicit ReaderFileProvider(const RunOptions& o) : o_(o) {}
  std::string canonical(const std::string& path) const override {
    std::error_code ec;
    return fs::absolute(path, ec).lexically_normal().string();
  }
  core::Result<std::string> read(const std::string& path) const override {
    auto r = o_.read_file(path);
    if (r) return r;
    // The loader's kinds: InvalidInput is a file too large; anything else
    // (a file outside the folder among them) a file it cannot read.
    return core::Error{
        r.error().code == core::ErrorCode::Overflow ? core::ErrorCode::InvalidInput : core::ErrorCode::Io,
        r.error().message};
  }

 private:
  const RunOptions& o_;
};

using Loaded = core::Result<void, Error>;

// Compiles the mission with `files` (null: the disk); its diagnostics
// (warnings too) are kept in `loaded`.
Loaded load_coral(const std::string& path, const coral::FileProvider* files, tactical::ExecutionLevel level,
                  LoadedMission& loaded) {
  // Checked for the vehicle it is to run on: an IMC vehicle's refusals
  // stop the run here, before anything starts.
  CoralLoad load = load_coral_file(path, loaded.catalogue, files, level);
  std::optional<Error> failed = load.error();
  loaded.diagnostics = std::move(load.diagnostics);
  loaded.sources = std::move(load.sources);
  if (failed) {
    failed->message += "; not running";
    return *failed;
  }
  if (!load.program->mission) {
    return Error{ErrorKind::Invalid, "",
                 fmt::format("{}: error: no `mission` net to run (the file holds only phase nets)", path),
                 Place{path, 0, 0}};
  }
  loaded.program = std::move(load.program);
  const coral::CompiledNet& mission = loaded.program->nets[*loaded.program->mission];
  loaded.name = mission.name;
  loaded.data_path = mission.data_file;
  return {};
}

// What a compile read, for RunOptions::keep_mission: every file's text (or
// that it could not be read) and every name looked up, in order.
class RecordingFileProvider final : public coral::FileProvider {
 public:
  struct Read {
    std::string path;
    std::optional<std::string> text;  // nullopt: not readable
  };
  struct Lookup {
    std::string path;
    bool exists = false;
  };

  explicit RecordingFileProvider(const coral::FileProvider& base) : base_(base) {}
  std::string canonical(const std::string& path) const override { return base_.canonical(path); }
  core::Result<std::string> read(const std::string& path) const override {
    auto r = base_.read(path);
    reads_.push_back({path, r ? std::optional<std::string>(r.value()) : std::nullopt});
    return r;
  }
  bool exists(const std::string& path) const override {
    const bool found = base_.exists(path);
    lookups_.push_back({path, found});
    return found;
  }

  std::vector<Read> take_reads() { return std::move(reads_); }
  std::vector<Lookup> take_lookups() { return std::move(lookups_); }

 private:
  const coral::FileProvider& base_;
  mutable std::vector<Read> reads_;
  mutable std::vector<Lookup> lookups_;
};

// A CORAL mission compiled and verified, kept for the next run of it in
// this process (RunOptions::keep_mission).
struct KeptCoral {
  std::string key;  // the mission's path, the folder, the vehicle, STRATA_LIBRARY
  std::vector<RecordingFileProvider::Read> reads;
  std::vector<RecordingFileProvider::Lookup> lookups;
  core::SourceManager sources;
  std::vector<core::Diagnostic> diagnostics;
  coral::Program program;
  coral::VerifyReport verification;
  std::string name, data_path;
};

// A worker runs a spec's few missions: the most kept at once, the least
// recently used going first.
constexpr std::size_t kMaxKeptCoral = 4;
std::mutex g_kept_mutex;
std::vector<std::shared_ptr<const KeptCoral>> g_kept_coral;  // most recent first

bool reads_the_same(const KeptCoral& kept, const coral::FileProvider& files) {
  for (const auto& r : kept.reads) {
    auto now = files.read(r.path);
    if (now.ok() != r.text.has_value() || (now && now.value() != *r.text)) return false;
  }
  return std::all_of(kept.lookups.begin(), kept.lookups.end(),
                     [&files](const auto& l) { return files.exists(l.path) == l.exists; });
}

// The kept mission of key that still reads the same, or null.
std::shared_ptr<const KeptCoral> take_kept(const std::string& key, const coral::FileProvider& files) {
  std::shared_ptr<const KeptCoral> kept;
  {
    std::lock_guard lock(g_kept_mutex);
    auto it = std::find_if(g_kept_coral.begin(), g_kept_coral.end(), [&key](const auto& k) { return k->key == key; });
    if (it == g_kept_coral.end()) return nullptr;
    kept = *it;
    std::rotate(g_kept_coral.begin(), it, it + 1);
  }
  if (reads_the_same(*kept, files)) return kept;
  std::lock_guard lock(g_kept_mutex);
  std::erase(g_kept_coral, kept);
  return nullptr;
}

void keep(std::shared_ptr<const KeptCoral> kept) {
  std::lock_guard lock(g_kept_mutex);
  std::erase_if(g_kept_coral, [&kept](const auto& k) { return k->key == kept->key; });
  g_kept_coral.insert(g_kept_coral.begin(), std::move(kept));
  if (g_kept_coral.size() > kMaxKeptCoral) g_kept_coral.resize(kMaxKeptCoral);
}

void compute_verification(LoadedMission& loaded) {
  coral::VerifyOptions vo;
  vo.mission_only = true;                       // what this run can reach
  vo.timing = bound_options(loaded.catalogue);  // the mission's `require`
  loaded.verification = coral::verify_program(*loaded.program, vo);
}

// The mission compiled (and, when it is kept, verified) or taken back.
Loaded load_coral(const RunOptions& o, LoadedMission& loaded) {
  std::optional<ReaderFileProvider> reader;
  if (o.read_file) reader.emplace(o);
  coral::DiskFileProvider disk;
  const coral::FileProvider& files = reader ? static_cast<const coral::FileProvider&>(*reader) : disk;
  const tactical::ExecutionLevel level = tactical::execution_level_of(o.vehicle);
  std::error_code ec;
  // Only the built-in catalogue: a --catalogue file is read afresh by every run.
  if (!o.keep_mission || !o.catalogue.empty()) return load_coral(o.mission, &files, level, loaded);
  // The library folders come from STRATA_LIBRARY (coral/loader.h): another
  // value looks elsewhere, so it is part of the key.
  const char* library = std::getenv("STRATA_LIBRARY");
  const std::string key = fmt::format("{}\n{}\n{}\n{}", o.mission, fs::current_path(ec).string(),
                                      tactical::execution_level_name(level), library ? library : "");
  if (auto kept = take_kept(key, files)) {
    loaded.sources = kept->sources;
    loaded.diagnostics = kept->diagnostics;
    loaded.program = kept->program;
    loaded.verification = kept->verification;
    loaded.name = kept->name;
    loaded.data_path = kept->data_path;
    loaded.taken_back = true;
    return {};
  }
  RecordingFileProvider recording(files);
  Loaded r = load_coral(o.mission, &recording, level, loaded);
  if (!r) return r;
  compute_verification(loaded);
  auto kept = std::make_shared<KeptCoral>();
  kept->key = key;
  kept->reads = recording.take_reads();
  kept->lookups = recording.take_lookups();
  kept->sources = loaded.sources;
  kept->diagnostics = loaded.diagnostics;
  kept->program = *loaded.program;
  kept->verification = *loaded.verification;
  kept->name = loaded.name;
  kept->data_path = loaded.data_path;
  keep(std::move(kept));
  return {};
}

// Loads and checks the rules; their messages (warnings too) are kept in `loaded`.
Loaded load_prolog(const RunOptions& o, LoadedMission& loaded) {
  const std::string& path = o.mission;
  core::DiagnosticSink sink;
  const strategic::KeepRules keep = o.keep_mission  ? strategic::KeepRules::Yes
                                    : o.reuse_rules ? strategic::KeepRules::Reproducible
                                                    : strategic::KeepRules::No;
  auto rules = strategic::PrologMission::load(path, loaded.catalogue, loaded.sources, sink, load_limits(o.rule_load),
                                              keep, tactical::execution_level_of(o.vehicle));
  loaded.diagnostics = sink.diagnostics();
  if (!rules) {
    Error e = input_error(rules.error());
    e.message += "; not running";
    return e;
  }
  loaded.rules = std::move(rules.value());
  loaded.name = loaded.rules->name();
  loaded.data_path = loaded.rules->data_file();
  return {};
}

// The answers file read, parsed and checked against the mission.
Loaded load_answers(const RunOptions& o, LoadedMission& loaded) {
  auto text = o.read_file ? o.read_file(o.answers) : core::read_regular_file(o.answers, kMaxAnswersFileBytes);
  if (!text) return input_error(text.error(), "--answers");
  auto script = parse_answers(text.value(), o.answers);
  if (script) {
    if (auto checked = check_answers(script.value(), loaded.catalogue, loaded.program ? &*loaded.program : nullptr);
        !checked) {
      script = checked.error();
    }
  }
  if (!script) {
    Error e = input_error(script.error(), "--answers");
    e.message += "; not running";
    return e;
  }
  loaded.answers = std::move(script).value();
  return {};
}

// CORAL: the nets are verified before anything moves (a kept mission's
// verification came with it).
Loaded verify(const RunOptions& o, LoadedMission& loaded) {
  if (!loaded.verification) compute_verification(loaded);
  if (loaded.verification->ok() || o.unverified || !o.answers.empty()) return {};
  return Error{ErrorKind::FailsVerification, "",
               fmt::format("{} fails verification; not running (`strata verify {}` shows every property; "
                           "--unverified runs it anyway, and its log records that)",
                           o.mission, o.mission),
               std::nullopt};
}

Loaded load_vehicle_inputs(const RunOptions& o, LoadedMission& loaded) {
  loaded.params = vehicle::default_params();
  if (!o.params.empty()) {
    auto p = vehicle::load_params(o.params);
    if (!p) return input_error(p.error());
    loaded.params = p.value();
  }
  for (const auto& [name, value] : o.param_overrides) {
    if (auto r = vehicle::set_param(loaded.params, name, value); !r) {
      return Error{ErrorKind::Invalid, "vehicle parameter override", r.error().message, std::nullopt};
    }
  }
  if (!o.param_overrides.empty()) {
    if (auto r = vehicle::check_param_relations(loaded.params); !r) {
      return Error{ErrorKind::Invalid, "vehicle parameter overrides", r.error().message, std::nullopt};
    }
  }
  auto scenario = o.read_file ? load_scenario_through(o.read_file, o.scenario, o.mission)
                              : load_scenario_option(o.scenario, o.mission);
  if (!scenario) return input_error(scenario.error());
  loaded.scenario = std::move(scenario.value());
  loaded.scenario_origin = scenario_origin(o);
  if (!o.vehicle.empty() && (!o.scenario.empty() || !o.params.empty() || !o.param_overrides.empty() || o.realtime)) {
    return Error{ErrorKind::Usage, "",
                 "--scenario, --params and --realtime set up the embedded vehicle; with "
                 "--vehicle they belong to that vehicle's own command line",
                 std::nullopt};
  }
  return {};
}

Loaded load_data(const RunOptions& o, LoadedMission& loaded) {
  if (!o.data.empty()) loaded.data_path = o.data;
  if (loaded.data_path.empty()) return {};
  const tactical::DataLimits limits{loaded.params.tank_depth_m};
  core::Result<tactical::MissionData> d = core::Error{core::ErrorCode::Internal, "not read"};
  if (o.read_file) {
    auto text = o.read_file(loaded.data_path);
    d = text ? tactical::MissionData::parse(text.value(), loaded.data_path, limits)
             : core::Result<tactical::MissionData>(core::Error{
                   core::ErrorCode::Io, fmt::format("cannot read the mission data file: {}", text.error().message)});
  } else {
    d = tactical::MissionData::load(loaded.data_path, limits);
  }
  if (!d) return input_error(d.error());
  loaded.data = std::move(d.value());
  loaded.cursor.emplace(*loaded.data);
  return {};
}

}  // namespace

core::Result<void, Error> load_mission(const RunOptions& o, LoadedMission& loaded) {
  const core::MissionLanguage language = core::mission_language(o.mission);
  if (language == core::MissionLanguage::None) {
    return Error{ErrorKind::Usage, "",
                 fmt::format("'{}': a mission is a .coral file (CORAL) or a .pl file (PROLOG)", o.mission),
                 std::nullopt};
  }
  auto catalogue = load_catalogue_option(o.catalogue);
  if (!catalogue) return input_error(catalogue.error());
  loaded.catalogue = std::move(catalogue.value());
  Loaded r = language == core::MissionLanguage::Prolog ? load_prolog(o, loaded) : load_coral(o, loaded);
  if (r && !o.answers.empty()) r = load_answers(o, loaded);
  if (r && loaded.program) r = verify(o, loaded);
  if (r) r = load_vehicle_inputs(o, loaded);
  if (r) r = load_data(o, loaded);
  return r;
}

strategic::LoadLimits load_limits(const RuleLoadLimits& limits) {
  strategic::LoadLimits l;
  l.time = std::chrono::milliseconds(static_cast<std::int64_t>(limits.time_s * 1000.0));
  l.inferences = limits.inferences;
  l.max_bytes = static_cast<std::size_t>(limits.max_bytes);
  return l;
}

std::string scenario_origin(const RunOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!o.scenario.empty()) {
    if (o.read_file || o.mission.empty() || fs::is_regular_file(o.scenario, ec)) return o.scenario;
    return scenario_path(o.mission, o.scenario).string();
  }
  if (o.mission.empty()) return "built in";
  std::string nominal = scenario_path(o.mission, "nominal").string();
  const bool found = o.read_file ? o.read_file(nominal).ok() : fs::is_regular_file(nominal, ec);
  if (found) return nominal;
  return fmt::format("built in: no {} beside the mission", (fs::path("scenarios") / "nominal.toml").string());
}

std::string scenario_name(const RunOptions& o) { return o.scenario.empty() ? "nominal" : o.scenario; }

tactical::RunInfo run_info(const RunOptions& o, const LoadedMission& loaded) {
  const bool embedded = o.vehicle.empty();
  tactical::RunInfo info;
  info.version = kVersion;
  info.mission = o.mission;
  info.mission_sha256 = sha256_or_empty(o, o.mission);
  info.data = loaded.data_path;
  if (!loaded.data_path.empty()) info.data_sha256 = sha256_or_empty(o, loaded.data_path);
  info.scenario = embedded ? scenario_name(o) : "external";
  info.seed = embedded ? loaded.scenario.seed : 0;
  if (embedded && !o.params.empty()) {
    info.params = o.params;
    info.params_sha256 = sha256_or_empty(o, o.params);
  }
  if (embedded) info.param_overrides = o.param_overrides;
  info.clock = o.realtime ? "wall" : "lockstep";
  return info;
}

nlohmann::json verification_record(const coral::VerifyReport& v, bool unverified) {
  nlohmann::json failed = nlohmann::json::array(), warnings = nlohmann::json::array();
  std::uint64_t states = 0;
  for (const auto& n : v.nets) {
    states += n.states;
    for (const auto& p : n.properties) {
      if (p.status == coral::Property::Status::Holds) continue;
      (p.blocking ? failed : warnings)
          .push_back(
              {{"net", n.name}, {"property", p.key}, {"status", coral::status_name(p.status)}, {"message", p.message}});
    }
  }
  nlohmann::json j{{"event", "verification"}, {"ok", v.ok()}, {"nets", v.nets.size()}, {"states", states}};
  if (!warnings.empty()) j["warnings"] = std::move(warnings);
  if (!v.ok()) {
    j["failed"] = std::move(failed);
    j["run_anyway"] = unverified;  // --unverified, or --answers following a witness
  }
  return j;
}

}  // namespace strata::run
