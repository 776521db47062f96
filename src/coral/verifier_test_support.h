#pragma once
// What the verifier's tests share (verifier_test.cpp, verifier_limits_test.cpp):
// a property of a verified net by its key, a counterexample's steps as
// text, and a mission's text compiled and verified.
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "coral/test_support.h"
#include "coral/verifier.h"
#include "coral/verify_report.h"

namespace strata::coral::testing {

inline const Property& property(const NetVerification& n, std::string_view key) {
  for (const auto& p : n.properties) {
    if (p.key == key) return p;
  }
  throw std::runtime_error("no property " + std::string(key));
}

inline std::vector<std::string> steps(const Property& p) {
  std::vector<std::string> out;
  if (p.counterexample) {
    for (const auto& s : p.counterexample->steps) out.push_back(step_text(s));
  }
  return out;
}

inline VerifyReport verify_text_mission(const std::string& text,
                                        const std::vector<std::pair<std::string, std::string>>& extra = {}) {
  auto c = compile_text(text, extra);
  if (!c->program) {
    std::string all;
    for (const auto& k : c->kinds()) all += k + "\n";
    ADD_FAILURE() << "does not compile:\n" << all;
    return {};
  }
  return verify_program(*c->program);
}

}  // namespace strata::coral::testing
