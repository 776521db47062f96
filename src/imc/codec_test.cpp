#include <gtest/gtest.h>

#include "imc/codec.h"

namespace strata::imc {
namespace {

TEST(ImcCodec, HeartbeatRoundTrips) {
  Packet p{Header{}, Heartbeat{}};
  auto bytes = encode(p);
  ASSERT_TRUE(bytes.ok());
  auto back = decode(bytes.value());
  ASSERT_TRUE(std::holds_alternative<Packet>(back));
}

}  // namespace
}  // namespace strata::imc
