#include "sonar/manager.h"

#include <cmath>
#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sonar/output.h"

namespace strata::sonar {
namespace {

using Json = nlohmann::ordered_json;

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

Json frame_json(const FrameReport& f, const std::string& file, const CaptureItem& item) {
  Json j;
  j["event"] = "frame";
  j["time_s"] = round3(f.time_s);
  j["frame"] = f.frame;
  j["file"] = file;
  j["pings"] = f.pings;
  j["frame_pings"] = f.frame_pings;
  j["seq_gaps"] = item.seq_gaps;
  j["lost_pings"] = item.lost_pings;
  j["heading_deg"] = round3(f.vehicle.heading_deg);
  j["x_m"] = round3(f.vehicle.x_m);
  j["y_m"] = round3(f.vehicle.y_m);
  j["walls"] = Json::array();
  for (const auto& w : f.detection.walls) {
    j["walls"].push_back({{"x1_m", round3(w.x1_m)},
                          {"y1_m", round3(w.y1_m)},
                          {"x2_m", round3(w.x2_m)},
                          {"y2_m", round3(w.y2_m)},
                          {"distance_m", round3(w.distance_m)},
                          {"points", w.points}});
  }
  if (const auto& t = f.detection.target) {
    j["target"] = {{"x_m", round3(t->x_m)},
                   {"y_m", round3(t->y_m)},
                   {"range_m", round3(t->range_m)},
                   {"bearing_deg", round3(t->bearing_deg)},
                   {"pings", t->pings},
                   {"points", t->points}};
  } else {
    j["target"] = nullptr;
  }
  return j;
}

Json end_json(const ManagerSummary& s) {
  Json j;
  j["event"] = "end";
  j["outcome"] = outcome_name(s.outcome);
  j["message"] = s.message;
  j["time_s"] = round3(s.last_time_s);
  j["frames"] = s.frames;
  j["pings"] = s.capture.pings;
  j["processed"] = s.processed;
  j["unusable"] = s.unusable;
  j["seq_gaps"] = s.capture.seq_gaps;
  j["lost_pings"] = s.capture.lost_pings;
  j["garbage_bytes"] = s.capture.garbage_bytes;
  j["bad_frames"] = s.capture.bad_frames;
  j["queue_drops"] = s.capture.queue_drops;
  j["queue_peak"] = s.capture.queue_peak;
  j["bytes"] = s.capture.bytes;
  if (s.end) {
    j["vehicle_pings_sent"] = s.end->pings_sent;
    j["vehicle_pings_dropped"] = s.end->pings_dropped;
    j["vehicle_reason"] = s.end->reason;
  }
  return j;
}

std::string frame_line(const FrameReport& f, const std::string& file) {
  std::string text = fmt::format("sonar: {} ({} pings, t={:.1f} s): ", file, f.frame_pings, f.time_s);
  if (f.detection.walls.empty()) text += "no wall";
  for (std::size_t i = 0; i < f.detection.walls.size(); ++i) {
    text += fmt::format("{}wall at {:.2f} m", i ? ", " : "", f.detection.walls[i].distance_m);
  }
  if (const auto& t = f.detection.target) {
    text += fmt::format(", target at ({:.2f}, {:.2f}), {:.2f} m, {:+.0f} deg ({} pings)", t->x_m, t->y_m, t->range_m,
                        t->bearing_deg, t->pings);
  }
  return text;
}

std::string counts_text(const ManagerSummary& s) {
  const auto& c = s.capture;
  std::string text = fmt::format("{} pings, {} frames, {} lost in {} seq gaps, {} garbage bytes, {} bad frames",
                                 c.pings, s.frames, c.lost_pings, c.seq_gaps, c.garbage_bytes, c.bad_frames);
  if (s.end && s.end->pings_dropped > 0) text += fmt::format(", {} dropped by the vehicle", s.end->pings_dropped);
  if (c.queue_drops > 0) text += fmt::format("; processing fell behind: {} pings not processed", c.queue_drops);
  return text;
}

}  // namespace

int exit_code(Outcome outcome) {
  switch (outcome) {
    case Outcome::Ended:
    case Outcome::NeverStarted:
    case Outcome::Stopped: return 0;
    case Outcome::VehicleGone:
    case Outcome::NeverConnected: return 69;
    case Outcome::OutputFailed: return 74;
  }
  return 70;
}

const char* outcome_name(Outcome outcome) {
  switch (outcome) {
    case Outcome::Ended: return "ended";
    case Outcome::NeverStarted: return "never_started";
    case Outcome::VehicleGone: return "vehicle_gone";
    case Outcome::NeverConnected: return "never_connected";
    case Outcome::Stopped: return "stopped";
    case Outcome::OutputFailed: return "output_failed";
  }
  return "?";
}

ManagerSummary run_sonar_manager(const ManagerOptions& o, const std::stop_token& stop) {
  auto log = o.log ? o.log : [](const std::string& line) { std::cerr << line << std::endl; };
  ManagerSummary s;
  auto finish = [&](Outcome outcome, std::string message) {
    s.outcome = outcome;
    s.exit_code = exit_code(outcome);
    s.message = std::move(message);
  };
  auto out = OutputDir::open(o.out_dir);
  if (!out) {
    finish(Outcome::OutputFailed, out.error().message);
    log("sonar: " + s.message);
    return s;
  }

  FrameQueue queue(std::max<std::size_t>(o.queue_capacity, 1));
  Capture capture(o.capture, queue);
  std::stop_callback on_stop(stop, [&capture] { capture.stop(); });
  capture.start();
  Processor processor(o.processor);
  bool done = false;
  bool warned_behind = false;
  // Writes the frame, if any; when writing fails, the run is over.
  auto emit = [&](std::optional<FrameReport> frame, const CaptureItem& item) {
    if (!frame) return;
    auto file = out.value().write_frame(frame->frame, frame->image);
    auto line = file ? out.value().append_line(frame_json(*frame, file.value(), item).dump())
                     : core::Result<void>(file.error());
    if (!line) {
      finish(Outcome::OutputFailed, line.error().message);
      capture.stop();
      done = true;
      return;
    }
    ++s.frames;
    if (o.verbose) log(frame_line(*frame, file.value()));
  };
  while (!done) {
    auto item = queue.pop(std::chrono::milliseconds(100));
    if (!item) continue;  // the capture thread always ends its stream with SonarEnd or StreamClosed
    if (!warned_behind && queue.dropped() > 0) {
      warned_behind = true;
      log(
          fmt::format("sonar: processing is falling behind: {} pings wait in the queue, further pings are dropped "
                      "until it catches up",
                      queue.capacity()));
    }
    if (std::holds_alternative<StreamConnected>(item->what)) {
      if (!o.quiet)
        log(fmt::format("sonar: connected to {}:{}, writing frames to {}", o.capture.host, o.capture.port,
                        o.out_dir.string()));
    } else if (const auto* ping = std::get_if<protocol::SonarPing>(&item->what)) {
      if (o.before_ping) o.before_ping(*ping);
      s.last_time_s = ping->time_s;
      emit(processor.add_ping(*ping), *item);
    } else if (const auto* status = std::get_if<protocol::SonarStatus>(&item->what)) {
      s.last_status = *status;
      s.last_time_s = status->time_s;
      if (!status->on) emit(processor.flush(), *item);
    } else if (const auto* end = std::get_if<protocol::SonarEnd>(&item->what)) {
      s.end = *end;
      s.last_time_s = end->time_s;
      emit(processor.flush(), *item);
      if (done) break;
      if (capture.counts().pings == 0) {
        finish(Outcome::NeverStarted, "the sonar never started: no pings");
      } else {
        finish(Outcome::Ended, end->reason.empty() ? "the sonar stream ended"
                                                   : fmt::format("the sonar stream ended ({})", end->reason));
      }
      done = true;
    } else {
      const auto& closed = std::get<StreamClosed>(item->what);
      emit(processor.flush(), *item);
      if (done) break;
      if (closed.stopped) {
        finish(Outcome::Stopped, "stopped before the stream ended");
      } else if (!closed.connected) {
        finish(Outcome::NeverConnected, closed.why);
      } else {
        finish(Outcome::VehicleGone,
               fmt::format("the vehicle went away without ending the sonar stream ({})", closed.why));
      }
      done = true;
    }
  }
  capture.stop();
  capture.join();
  s.capture = capture.counts();
  s.processed = processor.pings();
  s.unusable = processor.unusable();
  if (s.outcome != Outcome::OutputFailed) {
    if (auto r = out.value().append_line(end_json(s).dump()); !r) finish(Outcome::OutputFailed, r.error().message);
  }
  const bool read_nothing = s.outcome == Outcome::NeverConnected || s.capture.bytes == 0;
  log(read_nothing ? "sonar: " + s.message : fmt::format("sonar: {}: {}", s.message, counts_text(s)));
  return s;
}

}  // namespace strata::sonar
