#include "tactical/mission_log.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <iterator>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace strata::tactical {
namespace {

using nlohmann::ordered_json;
using namespace std::chrono_literals;

// A wall clock that starts at `start` and moves on by `step` at every reading.
WallTimeSource fake_clock(std::chrono::system_clock::time_point start, std::chrono::microseconds step) {
  auto wall = std::make_shared<std::chrono::system_clock::time_point>(start);
  auto mono = std::make_shared<std::chrono::steady_clock::time_point>();
  return {[wall, step] { return *wall += step; }, [mono, step] { return *mono += step; }};
}

RunInfo tank_run() {
  RunInfo run;
  run.version = "0.1.0";
  run.mission = "missions/tank/tank.coral";
  run.mission_sha256 = "ab";
  run.data = "missions/tank/setpoints.toml";
  run.data_sha256 = "cd";
  run.scenario = "nominal";
  run.seed = 7;
  run.clock = "lockstep";
  return run;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh directory under the system's temp folder, removed afterwards.
class TempDir {
 public:
  TempDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("strata_tactical_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

// One short run's worth of events.
void play(MissionLog& log) {
  log.request(1, "next_setpt_data", "exec setpoint 0.6 30", 0.0);
  log.reply(1, "done", 0.1);
  log.request(2, "sleep", "exec sleep 1", 0.1);
  log.telemetry(0.6, ordered_json{{"depth_m", 0.12}, {"depth_rate_mps", 0.3}});
  log.reply(2, "done", 1.1);
  log.request(3, "depth_reached", "ask depth_reached", 1.1);
  log.reply(3, 1, 1.2);
  log.report("phase 2 complete", 1.2);
  log.event("firing", ordered_json{{"net", "dive_from_surface"}, {"transition", "depth_ok"}, {"sim_time", 1.2}});
  log.error("link lost", 1.3);
}

TEST(MissionLog, TheHeaderComesFirst) {
  std::ostringstream out;
  auto log =
      MissionLog::to_stream(out, tank_run(), fake_clock(std::chrono::system_clock::time_point(1700000000s), 0us));
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(1u, log.value().lines());
  EXPECT_EQ(R"({"event":"run","version":"0.1.0","mission":"missions/tank/tank.coral","mission_sha256":"ab",)"
            R"("data":"missions/tank/setpoints.toml","data_sha256":"cd","scenario":"nominal","seed":7,)"
            R"("clock":"lockstep","wall_time":"2023-11-14T22:13:20.000000Z"})"
            "\n",
            out.str());
}

TEST(MissionLog, NoDataFileIsNull) {
  RunInfo run = tank_run();
  run.data.clear();
  auto header = run_header(run, std::chrono::system_clock::time_point());
  EXPECT_TRUE(header["data"].is_null());
  EXPECT_TRUE(header["data_sha256"].is_null());
}

// A perturbed campaign case's log says which vehicle it ran: the parameter
// file it started from and the values set over it (issue 21).
TEST(MissionLog, TheHeaderNamesTheVehicleParametersWhenTheyAreNotTheBuiltInOnes) {
  RunInfo run = tank_run();
  EXPECT_FALSE(run_header(run, {}).contains("params"));
  EXPECT_FALSE(run_header(run, {}).contains("param_overrides"));
  run.params = "heavy.toml";
  run.params_sha256 = "ef";
  run.param_overrides = {{"hull.mass_kg", 175.5}, {"thrusters.max_thrust_n", 40.0}};
  auto header = run_header(run, {});
  EXPECT_EQ("heavy.toml", header["params"]);
  EXPECT_EQ("ef", header["params_sha256"]);
  EXPECT_EQ(R"({"hull.mass_kg":175.5,"thrusters.max_thrust_n":40.0})", header["param_overrides"].dump());
}

TEST(MissionLog, OneLinePerEventWithFixedKeyOrder) {
  std::ostringstream out;
  auto log = MissionLog::to_stream(out, tank_run(), fake_clock({}, 250us));
  ASSERT_TRUE(log.ok());
  play(log.value());
  auto lines = lines_of(out.str());
  ASSERT_EQ(11u, lines.size());
  EXPECT_EQ(11u, log.value().lines());
  EXPECT_EQ(
      R"({"event":"request","id":1,"primitive":"next_setpt_data","message":"exec setpoint 0.6 30","sim_time":0.0})",
      lines[1]);
  EXPECT_EQ(R"({"event":"reply","id":1,"result":"done","sim_time":0.1,"latency_sim_s":0.1,"wall_latency_us":250})",
            lines[2]);
  EXPECT_EQ(R"({"event":"telemetry","sim_time":0.6,"depth_m":0.12,"depth_rate_mps":0.3})", lines[4]);
  // 1.1 - 0.1 is 1.0000000000000002 in doubles: the log rounds to the microsecond.
  EXPECT_EQ(R"({"event":"reply","id":2,"result":"done","sim_time":1.1,"latency_sim_s":1.0,"wall_latency_us":250})",
            lines[5]);
  EXPECT_EQ(R"({"event":"reply","id":3,"result":1,"sim_time":1.2,"latency_sim_s":0.1,"wall_latency_us":250})",
            lines[7]);
  EXPECT_EQ(R"({"event":"report","text":"phase 2 complete","sim_time":1.2})", lines[8]);
  EXPECT_EQ(R"({"event":"firing","net":"dive_from_surface","transition":"depth_ok","sim_time":1.2})", lines[9]);
  EXPECT_EQ(R"({"event":"error","message":"link lost","sim_time":1.3})", lines[10]);
}

// Issue 39: a runaway mission wrote 127 MB of log. Bounded: past the bound
// less its reserve, one log_limit line and one call; past the bound nothing.
TEST(MissionLog, ABoundedLogSaysWhereItWasCutCallsOnceAndNeverPassesItsBound) {
  std::ostringstream out;
  auto log = MissionLog::to_stream(out, tank_run(), fake_clock({}, 0us));
  ASSERT_TRUE(log.ok());
  int calls = 0;
  const std::uint64_t bound = 8192;  // reserve: 1 KB
  log.value().limit(bound, [&] { ++calls; });
  for (int i = 0; i < 500; ++i) log.value().report("a line of some length, written again and again", i * 0.1);
  EXPECT_EQ(1, calls);
  EXPECT_TRUE(log.value().full());
  EXPECT_LE(out.str().size(), bound);
  EXPECT_EQ(out.str().size(), log.value().bytes());
  EXPECT_GT(log.value().dropped(), 300u);
  const std::string text = out.str();
  const auto cut = text.find("{\"event\":\"log_limit\",\"max_bytes\":8192,\"bytes\":");
  ASSERT_NE(std::string::npos, cut) << text;
  EXPECT_LE(cut, bound - 1024) << "said before the reserve";
  EXPECT_GT(text.size() - cut, 512u) << "lines after it, in the reserve";
  EXPECT_TRUE(log.value().status().ok());
}

TEST(MissionLog, AReplyToAnUnknownIdHasNoLatency) {
  std::ostringstream out;
  auto log = MissionLog::to_stream(out, tank_run(), fake_clock({}, 1us));
  ASSERT_TRUE(log.ok());
  log.value().reply(42, "done", 3.0);
  EXPECT_EQ(R"({"event":"reply","id":42,"result":"done","sim_time":3.0,"latency_sim_s":null,"wall_latency_us":null})",
            lines_of(out.str()).back());
}

TEST(MissionLog, EveryLineIsOnDiskAsSoonAsItIsWritten) {
  TempDir dir;
  auto path = dir.path() / "run.jsonl";
  auto log = MissionLog::open(path.string(), tank_run(), fake_clock({}, 1us));
  ASSERT_TRUE(log.ok()) << log.error().message;
  EXPECT_EQ(path.string(), log.value().path());
  auto on_disk = [&] { return lines_of(read_file(path)); };
  ASSERT_EQ(1u, on_disk().size());
  EXPECT_EQ(0u, on_disk()[0].rfind(R"({"event":"run",)", 0));
  log.value().request(1, "submerge", "exec submerge", 2.0);
  ASSERT_EQ(2u, on_disk().size());
  EXPECT_EQ(0u, on_disk()[1].rfind(R"({"event":"request","id":1,)", 0));
  log.value().reply(1, "done", 2.1);
  ASSERT_EQ(3u, on_disk().size());
  log.value().report("at depth", 2.1);
  ASSERT_EQ(4u, on_disk().size());
  EXPECT_EQ(R"({"event":"report","text":"at depth","sim_time":2.1})", on_disk()[3]);
  EXPECT_TRUE(log.value().status().ok());
}

TEST(MissionLog, TwoRunsDifferOnlyInWallFields) {
  std::ostringstream a, b;
  auto log_a =
      MissionLog::to_stream(a, tank_run(), fake_clock(std::chrono::system_clock::time_point(1700000000s), 100us));
  auto log_b =
      MissionLog::to_stream(b, tank_run(), fake_clock(std::chrono::system_clock::time_point(1800000000s), 7us));
  ASSERT_TRUE(log_a.ok() && log_b.ok());
  play(log_a.value());
  play(log_b.value());
  EXPECT_NE(a.str(), b.str());
  EXPECT_EQ(strip_wall_fields_from_log(a.str()), strip_wall_fields_from_log(b.str()));
  auto header = lines_of(strip_wall_fields_from_log(a.str()))[0];
  EXPECT_EQ(std::string::npos, header.find("wall_"));
  EXPECT_NE(std::string::npos, header.find(R"("clock":"lockstep")"));
}

TEST(MissionLog, StripWallFields) {
  EXPECT_EQ(R"({"b":1,"c":{"d":[{"e":2}]}})",
            strip_wall_fields(R"({"wall_a":1,"b":1,"c":{"wall_x":"t","d":[{"e":2,"wall_y":3}]}})"));
  EXPECT_EQ(R"({"wallet":1})", strip_wall_fields(R"({"wallet":1})"));  // only the wall_ prefix
  EXPECT_EQ("not json {", strip_wall_fields("not json {"));
}

TEST(MissionLog, InvalidUtf8IsReplacedNotThrown) {
  std::ostringstream out;
  auto log = MissionLog::to_stream(out, tank_run(), fake_clock({}, 1us));
  ASSERT_TRUE(log.ok());
  log.value().report(std::string("bad \xff byte"), 0);
  EXPECT_EQ(2u, log.value().lines());
  EXPECT_NE(std::string::npos, out.str().find("bad \xEF\xBF\xBD byte"));
}

TEST(MissionLog, ClockMustBeLockstepOrWall) {
  std::ostringstream out;
  RunInfo run = tank_run();
  run.clock = "sundial";
  auto log = MissionLog::to_stream(out, run, fake_clock({}, 1us));
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(core::ErrorCode::InvalidInput, log.error().code);
  EXPECT_TRUE(out.str().empty());
}

TEST(MissionLog, AnUnwritablePathIsAnIoError) {
  TempDir dir;
  auto log = MissionLog::open((dir.path() / "no" / "such" / "dir.jsonl").string(), tank_run(), fake_clock({}, 1us));
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(core::ErrorCode::Io, log.error().code);
}

std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// --log FILE: a regular file there is replaced, whole.
TEST(MissionLog, AnExistingRegularFileIsReplaced) {
  TempDir dir;
  const auto path = dir.path() / "old.jsonl";
  std::ofstream(path) << std::string(5000, 'x');
  {
    auto log = MissionLog::open(path.string(), tank_run(), fake_clock({}, 1us));
    ASSERT_TRUE(log.ok()) << log.error().message;
  }
  const std::string text = file_text(path);
  EXPECT_EQ(std::string::npos, text.find('x'));
  EXPECT_EQ(0u, text.find("{\"event\":\"run\""));
}

// Regression: the log was opened with an ofstream, which wrote through a
// link planted at its name into whatever it pointed at.
TEST(MissionLog, ALinkAtTheLogsNameIsNeverWrittenThrough) {
  TempDir dir;
  const auto victim = dir.path() / "victim.txt";
  std::ofstream(victim) << "untouched\n";
  std::filesystem::create_symlink(victim, dir.path() / "run.jsonl");
  auto log = MissionLog::open((dir.path() / "run.jsonl").string(), tank_run(), fake_clock({}, 1us));
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(core::ErrorCode::Io, log.error().code);
  EXPECT_NE(std::string::npos, log.error().message.find("symbolic link")) << log.error().message;
  EXPECT_EQ("untouched\n", file_text(victim));
}

// Regression: a FIFO at the log's name held the run at the open for ever.
TEST(MissionLog, AFifoAtTheLogsNameIsRefusedAtOnce) {
  TempDir dir;
  const auto fifo = dir.path() / "run.jsonl";
  ASSERT_EQ(0, ::mkfifo(fifo.c_str(), 0600));
  auto log = MissionLog::open(fifo.string(), tank_run(), fake_clock({}, 1us));
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(core::ErrorCode::Io, log.error().code);
}

TEST(MissionLog, AFolderAtTheLogsNameIsRefused) {
  TempDir dir;
  auto log = MissionLog::open(dir.path().string(), tank_run(), fake_clock({}, 1us));
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(core::ErrorCode::Io, log.error().code);
}

TEST(MissionLog, ADatedLogIsAlwaysANewFileNamedForTheMissionsFile) {
  TempDir dir;
  const std::string folder = (dir.path() / "logs").string();  // made when missing
  std::vector<std::string> names;
  for (int i = 0; i < 3; ++i) {
    auto log = MissionLog::open_dated(folder, "missions/tank/tank.coral", tank_run(), fake_clock({}, 1us));
    ASSERT_TRUE(log.ok()) << log.error().message;
    names.push_back(std::filesystem::path(log.value().path()).filename().string());
  }
  // Three in one second, unless the second turned: each a file of its own.
  EXPECT_NE(names[0], names[1]);
  EXPECT_NE(names[1], names[2]);
  for (const auto& n : names) {
    EXPECT_NE(std::string::npos, n.find("Z-tank.coral")) << n;
    EXPECT_TRUE(n.ends_with(".jsonl")) << n;
  }
}

// A script that runs one mission more than 100 times in a second (a
// campaign's cases as processes) got exit 74 from the 101st: "100 logs of
// 'tank.coral' in one second already; not logging".
TEST(MissionLog, TheHundredAndFirstLogOfAMissionInOneSecondIsStillWritten) {
  TempDir dir;
  const std::string folder = dir.path().string();
  const auto now = std::chrono::system_clock::now();
  std::set<std::string> made;
  // This second and the next two, in case the second turns meanwhile.
  for (int s = 0; s < 3; ++s) {
    for (int n = 1; n <= 150; ++n) {
      const std::string name = dated_log_name("tank.coral", now + std::chrono::seconds(s), n);
      std::ofstream(dir.path() / name) << "";
      made.insert(name);
    }
  }
  auto log = MissionLog::open_dated(folder, "missions/tank/tank.coral", tank_run(), fake_clock({}, 1us));
  ASSERT_TRUE(log.ok()) << log.error().message;
  const std::string name = std::filesystem::path(log.value().path()).filename().string();
  EXPECT_EQ(0u, made.count(name)) << name;
  EXPECT_TRUE(name.ends_with("Z-tank.coral-151.jsonl")) << name;  // the first name free
}

// A thousand runs of one mission starting at once (a campaign's cases as
// processes, two scripts at the same moment): each gets a log of its own,
// none is refused, none written over.
TEST(MissionLog, AThousandDatedLogsOpenedAtOnceAreEachANewFile) {
  TempDir dir;
  const std::string folder = dir.path().string();
  constexpr int kThreads = 8, kEach = 125;
  std::vector<std::vector<std::string>> names(kThreads);
  std::vector<std::string> errors(kThreads);
  std::vector<std::thread> threads;
  threads.reserve(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kEach; ++i) {
        auto log = MissionLog::open_dated(folder, "missions/tank/tank.coral", tank_run(), fake_clock({}, 1us));
        if (!log.ok()) {
          errors[t] = log.error().message;
          return;
        }
        names[t].push_back(log.value().path());
      }
    });
  }
  for (auto& th : threads) th.join();
  std::set<std::string> all;
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ("", errors[t]);
    all.insert(names[t].begin(), names[t].end());
  }
  EXPECT_EQ(static_cast<std::size_t>(kThreads * kEach), all.size());
}

TEST(MissionLog, TheDatedNameIsTheStartTimeInUtcAndTheFilesName) {
  const auto t = std::chrono::system_clock::from_time_t(1795643198);  // 2026-11-25T21:46:38Z
  EXPECT_EQ("20261125T214638Z-tank.coral.jsonl", dated_log_name("a/b/tank.coral", t));
  EXPECT_EQ("20261125T214638Z-tank.pl-3.jsonl", dated_log_name("tank.pl", t, 3));
}

TEST(MissionLog, AFailedWriteIsKept) {
  std::ostringstream out;
  auto log = MissionLog::to_stream(out, tank_run(), fake_clock({}, 1us));
  ASSERT_TRUE(log.ok());
  out.setstate(std::ios::badbit);
  log.value().report("lost", 1);
  EXPECT_FALSE(log.value().status().ok());
  EXPECT_EQ(core::ErrorCode::Io, log.value().status().error().code);
  EXPECT_EQ(1u, log.value().lines());
}

TEST(MissionLog, Times) {
  EXPECT_EQ("1970-01-01T00:00:01.500000Z", iso8601_utc(std::chrono::system_clock::time_point(1500ms)));
  EXPECT_EQ("1969-12-31T23:59:59.750000Z", iso8601_utc(std::chrono::system_clock::time_point(-250ms)));
  EXPECT_EQ(0.3, log_time(0.1 + 0.2));
  EXPECT_EQ(1.0, log_time(1.1 - 0.1));
}

}  // namespace
}  // namespace strata::tactical
