#pragma once
// Edits answered with a patch (docs/studio.md, "Edits"): the models the
// server last answered are kept by revision, and an edit of a page that
// names the model it holds (`base`) gets back what changed, not the whole
// model (1.3 MB for a 5,000-transition net).
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

namespace strata::studio {

// The last few models answered, each under a revision unique to this
// server (a random prefix: a page kept over a restart never matches a new
// server's revision). Threads: any.
class ModelCache {
 public:
  static constexpr std::size_t kEntries = 4;
  ModelCache();
  // Keeps `model` (a model about to be answered to a page) under a new
  // revision, set as its "rev", and returns it.
  std::shared_ptr<const nlohmann::json> keep(nlohmann::json model);
  // The model of `rev`, or null when it is not (or no longer) kept.
  std::shared_ptr<const nlohmann::json> find(const std::string& rev) const;

 private:
  mutable std::mutex mutex_;
  std::string prefix_;
  std::uint64_t next_ = 1;
  std::deque<std::pair<std::string, std::shared_ptr<const nlohmann::json>>> entries_;  // newest last
};

// What turns model `before` into model `after` (both mission models, `rev`
// ignored), as the page applies it (web/src/patch.js):
//   "text":  {"at": A, "remove": N, "insert": [lines]}: lines A..A+N-1
//            (0-based, split at '\n') of the old text replaced;
//   "shift": {"from": L, "by": D}: in a net marked "shift", every place and
//            transition whose line is L or more moves by D lines (the lines
//            the text edit inserted or removed above it);
//   "fields": the top-level members (not text, nets, rev) that changed, whole;
//   "drop":  the top-level members `after` no longer has;
//   "nets":  one entry per net of `after`, in order: {"net": the whole net}
//            for a net `before` lacks, else {"from": its index in before,
//            "shift": bool, "fields": changed members other than places and
//            transitions, "places": splice, "transitions": splice}, where a
//            splice {"at", "remove", "insert": [elements]} is applied to the
//            old array after the shift (absent: no change).
nlohmann::json model_patch(const nlohmann::json& before, const nlohmann::json& after);

}  // namespace strata::studio
