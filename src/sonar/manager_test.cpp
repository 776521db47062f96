// The Sonar Manager's run from connection to summary, against a test server
// on loopback: how each way a stream can end is told and written.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include "sonar/manager.h"
#include "sonar/output.h"
#include "core/file.h"
#include "sonar/png_io.h"
#include "sonar/test_support.h"

namespace strata::sonar {
namespace {

using testing::options_for;
using testing::PingSynth;
using testing::SynthConfig;
using testing::TestConnection;
using testing::TestServer;

std::vector<nlohmann::json> read_lines(const std::filesystem::path& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

// The server's part: status on, then `pings` pings of the synthesised tank.
void send_pings(TestConnection& c, int pings) {
  PingSynth synth(SynthConfig{});
  c.send(protocol::SonarStatus{0.0, true, 0, 0});
  for (int i = 0; i < pings; ++i) c.send(synth.next());
}

TEST(Manager, VehicleGoingAwayMidStreamIsSaidWrittenAndExits69) {
  TestServer server([](TestConnection& c) { send_pings(c, 190); });  // then closes: no SonarEnd
  std::vector<std::string> log;
  ManagerOptions o = options_for(server.port(), "gone");
  o.log = [&](const std::string& line) { log.push_back(line); };
  const ManagerSummary s = run_sonar_manager(o);
  EXPECT_EQ(Outcome::VehicleGone, s.outcome);
  EXPECT_EQ(69, s.exit_code);
  EXPECT_NE(std::string::npos, s.message.find("the vehicle went away")) << s.message;
  EXPECT_EQ(190u, s.processed);
  EXPECT_EQ(3u, s.frames);  // sweeps of 67 and 66 pings, then 57 of the third written as they were
  auto latest = read_png(o.out_dir / "latest.png");
  ASSERT_TRUE(latest) << latest.error().message;
  EXPECT_EQ(400, latest.value().width);
  for (int f = 1; f <= 3; ++f) EXPECT_TRUE(std::filesystem::exists(o.out_dir / scan_file_name(f))) << f;

  const auto lines = read_lines(o.out_dir / "sonar.jsonl");
  ASSERT_EQ(4u, lines.size());
  EXPECT_EQ("frame", lines[0]["event"]);
  EXPECT_EQ(1, lines[0]["frame"]);
  EXPECT_EQ("end", lines[3]["event"]);
  EXPECT_EQ("vehicle_gone", lines[3]["outcome"]);
  EXPECT_EQ(190, lines[3]["pings"]);
  // Always a start line and an end line, nothing per frame unless verbose.
  ASSERT_EQ(2u, log.size());
  EXPECT_NE(std::string::npos, log[0].find("connected to 127.0.0.1:")) << log[0];
  EXPECT_NE(std::string::npos, log[1].find("the vehicle went away")) << log[1];
}

TEST(Manager, VehicleResettingTheConnectionHasGoneAwayToo) {
  TestServer server([](TestConnection& c) {
    send_pings(c, 80);
    c.reset();
  });
  const ManagerSummary s = run_sonar_manager(options_for(server.port(), "reset"));
  EXPECT_EQ(Outcome::VehicleGone, s.outcome) << s.message;
  EXPECT_EQ(69, s.exit_code);
}

// A peer that accepts and says nothing (not a vehicle's sonar socket, or a
// listen queue nobody reads) is given up after the connect timeout, not
// waited on for ever.
TEST(Manager, APeerThatNeverSpeaksIsGivenUp) {
  TestServer server([](TestConnection&) { std::this_thread::sleep_for(std::chrono::milliseconds(3000)); });
  ManagerOptions o = options_for(server.port(), "silent_peer");
  o.capture.connect_timeout_s = 1.0;
  const ManagerSummary s = run_sonar_manager(o);
  EXPECT_EQ(Outcome::VehicleGone, s.outcome) << s.message;
  EXPECT_EQ(69, s.exit_code);
  EXPECT_NE(std::string::npos, s.message.find("nothing came from the vehicle")) << s.message;
}

TEST(Manager, SonarThatNeverStartsIsToldSoAndExits0) {
  TestServer server([](TestConnection& c) {
    c.send(protocol::SonarStatus{0.0, false, 0, 0});
    c.send(protocol::SonarEnd{120.0, 0, 0, "run over"});
  });
  ManagerOptions o = options_for(server.port(), "never_started");
  const ManagerSummary s = run_sonar_manager(o);
  EXPECT_EQ(Outcome::NeverStarted, s.outcome);
  EXPECT_EQ(0, s.exit_code);
  EXPECT_EQ("the sonar never started: no pings", s.message);
  EXPECT_EQ(0u, s.frames);
  const auto lines = read_lines(o.out_dir / "sonar.jsonl");
  ASSERT_EQ(1u, lines.size());
  EXPECT_EQ("never_started", lines[0]["outcome"]);
  EXPECT_FALSE(std::filesystem::exists(o.out_dir / "latest.png"));
}

TEST(Manager, NoVehicleWithinTheConnectTimeoutExits69) {
  ManagerOptions o = options_for(testing::closed_port(), "never_connected");
  o.capture.connect_timeout_s = 0.3;
  const ManagerSummary s = run_sonar_manager(o);
  EXPECT_EQ(Outcome::NeverConnected, s.outcome);
  EXPECT_EQ(69, s.exit_code);
  EXPECT_NE(std::string::npos, s.message.find("could not connect to 127.0.0.1:")) << s.message;
  EXPECT_NE(std::string::npos, s.message.find("refused")) << s.message;
  const auto lines = read_lines(o.out_dir / "sonar.jsonl");
  ASSERT_EQ(1u, lines.size());
  EXPECT_EQ("never_connected", lines[0]["outcome"]);
}

TEST(Manager, EndWritesTheSweepUnderWayThenTheSummary) {
  TestServer server([](TestConnection& c) {
    send_pings(c, 100);  // one sweep of 67 pings, then 33 of the next
    c.send(protocol::SonarEnd{5.0, 100, 3, "run over"});
  });
  std::vector<std::string> log;
  ManagerOptions o = options_for(server.port(), "end");
  o.verbose = true;
  o.log = [&](const std::string& line) { log.push_back(line); };
  const ManagerSummary s = run_sonar_manager(o);
  EXPECT_EQ(Outcome::Ended, s.outcome) << s.message;
  EXPECT_EQ(0, s.exit_code);
  EXPECT_EQ(2u, s.frames);
  const auto lines = read_lines(o.out_dir / "sonar.jsonl");
  ASSERT_EQ(3u, lines.size());
  EXPECT_EQ(67, lines[0]["frame_pings"]);
  EXPECT_EQ(33, lines[1]["frame_pings"]);
  EXPECT_EQ(100, lines[1]["pings"]);
  EXPECT_EQ("scan_00002.png", lines[1]["file"]);
  EXPECT_DOUBLE_EQ(7.0, lines[1]["x_m"].get<double>());
  EXPECT_DOUBLE_EQ(45.0, lines[1]["heading_deg"].get<double>());
  ASSERT_EQ(2u, lines[1]["walls"].size());  // the north wall 3.5 m away, the east wall 5 m
  std::vector<double> distances{lines[1]["walls"][0]["distance_m"], lines[1]["walls"][1]["distance_m"]};
  std::sort(distances.begin(), distances.end());
  EXPECT_NEAR(3.5, distances[0], 0.2);
  EXPECT_NEAR(5.0, distances[1], 0.2);
  EXPECT_TRUE(lines[1]["target"].is_null());
  const auto& end = lines[2];
  EXPECT_EQ("end", end["event"]);
  EXPECT_EQ("ended", end["outcome"]);
  EXPECT_EQ(100, end["pings"]);
  EXPECT_EQ(2, end["frames"]);
  EXPECT_EQ(3, end["vehicle_pings_dropped"]);
  EXPECT_EQ("run over", end["vehicle_reason"]);
  ASSERT_EQ(4u, log.size());  // connected, two frames (verbose), the end
  EXPECT_NE(std::string::npos, log[1].find("scan_00001.png")) << log[1];
  EXPECT_NE(std::string::npos, log[3].find("3 dropped by the vehicle")) << log[3];
}

TEST(Manager, StopWritesWhatItHasAndIsNoFailure) {
  TestServer server([](TestConnection& c) {
    send_pings(c, 100);
    c.wait_for_close(20.0);  // the vehicle keeps the stream open
  });
  ManagerOptions o = options_for(server.port(), "stop");
  std::atomic<int> processed{0};
  o.before_ping = [&](const protocol::SonarPing&) { ++processed; };
  ManagerSummary s;
  std::jthread run([&](std::stop_token stop) { s = run_sonar_manager(o, stop); });
  for (int i = 0; i < 1000 && processed.load() < 100; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(100, processed.load());
  run.request_stop();
  run.join();
  EXPECT_EQ(Outcome::Stopped, s.outcome);
  EXPECT_EQ(0, s.exit_code);
  EXPECT_EQ(2u, s.frames);
  const auto lines = read_lines(o.out_dir / "sonar.jsonl");
  ASSERT_EQ(3u, lines.size());
  EXPECT_EQ("stopped", lines[2]["outcome"]);
}

TEST(Manager, AFolderThatCannotBeMadeExits74WithoutConnecting) {
  const auto dir = testing::fresh_dir("not_a_folder");
  ASSERT_TRUE(core::write_file_atomically(dir / "file", "x"));
  ManagerOptions o = options_for(testing::closed_port(), "unused");
  o.out_dir = dir / "file" / "sonar";
  const ManagerSummary s = run_sonar_manager(o);
  EXPECT_EQ(Outcome::OutputFailed, s.outcome);
  EXPECT_EQ(74, s.exit_code);
  EXPECT_NE(std::string::npos, s.message.find("cannot create the folder")) << s.message;
}

TEST(Output, ReadLastLinesReadsOnlyTheTailAndWholeLines) {
  const auto dir = testing::fresh_dir("last_lines");
  {
    std::ofstream out(dir / "sonar.jsonl");
    for (int i = 1; i <= 2000; ++i)
      out << "{\"event\":\"frame\",\"frame\":" << i << ",\"pad\":\"" << std::string(40, 'x') << "\"}\n";
  }
  LastLines last = read_last_lines(dir, 4096);  // the file is about 100 KB
  EXPECT_NE(std::string::npos, last.frame.find("\"frame\":2000,")) << last.frame;
  EXPECT_EQ("", last.end);
  {
    std::ofstream out(dir / "sonar.jsonl", std::ios::app);
    out << "{\"event\":\"end\",\"frames\":2000}\n{\"event\":\"frame\",\"fra";  // a line being written
  }
  last = read_last_lines(dir, 4096);
  EXPECT_EQ("{\"event\":\"end\",\"frames\":2000}", last.end);
  EXPECT_NE(std::string::npos, last.frame.find("\"frame\":2000,"));
  EXPECT_EQ("", read_last_lines(dir / "none").frame);
}

// Regression: sonar.jsonl was opened with an ifstream, so a FIFO at that
// name (in a --sonar folder the studio was given) held the reader, the
// studio's /api/sonar, for ever.
TEST(Output, ReadLastLinesOfAFifoIsNoLinesNotAWait) {
  const auto dir = testing::fresh_dir("last_lines_fifo");
  ASSERT_EQ(0, ::mkfifo((dir / "sonar.jsonl").c_str(), 0600));
  const LastLines last = read_last_lines(dir);
  EXPECT_EQ("", last.frame);
  EXPECT_EQ("", last.end);
}

}  // namespace
}  // namespace strata::sonar
