#pragma once
// `strata run --sonar DIR`: the Sonar Manager as a separate process, as in
// the paper's Figure 1 — `strata sonar --stream HOST:PORT --out DIR`, the
// same executable, started beside the run and waited for after it.
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <asio.hpp>

#include "core/result.h"
#include "vehicle/sonar_server.h"

namespace strata::run {

class SonarChild {
 public:
  // Starts `<this executable> sonar --stream HOST:PORT --out DIR [extra...]`
  // with its standard output and error going to `log_path` (appended).
  static core::Result<SonarChild> start(const std::string& host, std::uint16_t port, const std::string& dir,
                                        const std::string& log_path, const std::vector<std::string>& extra = {});
  SonarChild(SonarChild&& other) noexcept : pid_(std::exchange(other.pid_, -1)) {}
  SonarChild& operator=(SonarChild&&) = delete;
  // Terminates the child if it is still running and reaps it.
  ~SonarChild();

  pid_t pid() const { return pid_; }
  // Waits up to `limit` for it to end; its exit status (128+N for a signal),
  // or nullopt if it is still running.
  std::optional<int> wait(std::chrono::milliseconds limit);
  // SIGTERM, then SIGKILL after `grace`; the exit status.
  int stop(std::chrono::milliseconds grace);

 private:
  explicit SonarChild(pid_t pid) : pid_(pid) {}
  pid_t pid_ = -1;
};

// The path of the running executable (/proc/self/exe).
std::string self_executable();

// `strata run --sonar DIR`: creates DIR and starts the manager on the
// vehicle's sonar socket (host, the port its hello announced; ErrorCode::
// InvalidInput when it announced none). With the embedded vehicle's sonar
// server given, waits (running io, at most 10 s) until the manager has
// connected, so a lockstep run loses no ping to a late start. Its output
// goes to DIR/manager.log.
core::Result<SonarChild> start_sonar_manager(const std::string& dir, const std::string& host,
                                             std::optional<std::uint16_t> port, asio::io_context& io,
                                             const vehicle::SonarServer* sonar);
// After the run: runs io (at most 10 s) until the embedded vehicle's sonar
// server has written everything to its readers and closed them.
void drain_sonar(asio::io_context& io, const vehicle::SonarServer* sonar);
// One line for the run's summary: the manager's exit and what its
// sonar.jsonl says.
std::string sonar_summary(const std::string& dir, std::optional<int> exit_status);

}  // namespace strata::run
