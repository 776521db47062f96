#include "tactical/execution_link.h"

namespace strata::tactical {

ExecutionLink::Hold& ExecutionLink::Hold::operator=(Hold&& other) noexcept {
  if (this != &other) {
    release();
    link_ = std::move(other.link_);
    other.link_.reset();
  }
  return *this;
}

void ExecutionLink::Hold::release() {
  auto link = link_.lock();
  link_.reset();
  if (!link) return;
  --link->holds_;
  link->hold_released();
}

ExecutionLink::Hold ExecutionLink::hold() {
  ++holds_;
  return Hold(weak_from_this());
}

}  // namespace strata::tactical
