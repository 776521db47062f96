#include "strategic/executor.h"

namespace strata::strategic {

bool ExecutorBase::begin(std::function<void(const MissionResult&)> on_end) {
  if (running_ || ended_) return false;
  on_end_ = std::move(on_end);
  running_ = true;
  return true;
}

void ExecutorBase::finish(const MissionResult& result) {
  if (!running_) return;
  running_ = false;
  ended_ = true;
  wind_down(result);
  observers_.mission_ended(result);
  if (on_end_) {
    auto on_end = std::move(on_end_);
    on_end_ = nullptr;
    on_end(result);
  }
}

}  // namespace strata::strategic
