// How a case reads the calls of its run: by their verb and error kind.
#include "campaign/case_run.h"

#include <gtest/gtest.h>

namespace strata::campaign {
namespace {

using tactical::CallError;
using tactical::CallRecord;

CallRecord exec_call(std::optional<bool> value, std::optional<CallError> error = std::nullopt) {
  CallRecord r;
  r.primitive = "submerge";
  r.verb = core::CallVerb::Exec;
  r.message = "exec submerge";
  r.value = value;
  r.error = std::move(error);
  return r;
}

TEST(RefusedExec, AnExecTheVehicleRefusedCountsWhateverItsMessageSays) {
  for (const char* words : {"vehicle refused `exec submerge` (request 3): failed: no network", "nope", ""}) {
    EXPECT_TRUE(
        refused_exec(exec_call(std::nullopt, CallError{CallError::Kind::Refused, protocol::ErrorCode::Failed, words})))
        << words;
  }
}

TEST(RefusedExec, AnExecAnsweredZeroCountsAndOneAnsweredOneDoesNot) {
  EXPECT_TRUE(refused_exec(exec_call(false)));
  EXPECT_FALSE(refused_exec(exec_call(true)));
}

TEST(RefusedExec, ATimeoutALostLinkOrACallNeverSentIsNoRefusal) {
  for (CallError::Kind k : {CallError::Kind::TimedOut, CallError::Kind::LinkLost, CallError::Kind::BadReply,
                            CallError::Kind::BadCall, CallError::Kind::Withheld}) {
    // Even worded like a refusal.
    EXPECT_FALSE(refused_exec(exec_call(std::nullopt, CallError{k, std::nullopt, "vehicle error failed: refused"})))
        << tactical::kind_name(k);
  }
}

TEST(RefusedExec, OnlyExecsCount) {
  CallRecord ask = exec_call(false);
  ask.verb = core::CallVerb::Ask;
  ask.message = "ask depth_reached";
  EXPECT_FALSE(refused_exec(ask));
  CallRecord ood = exec_call(std::nullopt, CallError{CallError::Kind::Refused, protocol::ErrorCode::Failed, "x"});
  ood.verb = core::CallVerb::Ood;
  EXPECT_FALSE(refused_exec(ood));
  CallRecord unknown = exec_call(std::nullopt, CallError{CallError::Kind::BadCall, std::nullopt, "unknown"});
  unknown.verb.reset();
  EXPECT_FALSE(refused_exec(unknown));
}

}  // namespace
}  // namespace strata::campaign
