#pragma once
// The markings a question's search (question.cpp) has visited. Not part of
// the API.
#include <cstdint>
#include <cstring>
#include <vector>

#include "petri/net.h"

namespace strata::petri::question_detail {

inline std::uint64_t question_mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The visited markings: packed one byte per place while every count is
// under 256, else four. The current marking is kept encoded beside them
// (set() per place changed), so a lookup encodes nothing, and so is its
// hash: sum of tokens(p) * key(p) (random odd keys, mod 2^64), mixed,
// updated by one multiply per place changed. The table holds (32 bits of
// hash, index) pairs: a probe that misses rarely reads a marking.
class MarkingStore {
 public:
  explicit MarkingStore(const Marking& initial) : places_(initial.size()) {
    table_.assign(1024, kEmptySlot);
    std::uint64_t seed = 0x2545F4914F6CDD1DULL;
    keys_.resize(places_);
    for (std::uint64_t& k : keys_) k = question_mix(seed += 0x9E3779B97F4A7C15ULL) | 1;
    for (Tokens v : initial) width_ = v > 255 ? 4 : width_;
    cur_.assign(places_ * width_, 0);
    for (PlaceId p = 0; p < places_; ++p) set(p, initial[p]);
  }

  std::uint64_t size() const { return count_; }
  std::size_t memory_bytes() const { return arena_.capacity() + table_.capacity() * 8 + cur_.capacity(); }

  // Place p of the current marking now holds v.
  void set(PlaceId p, Tokens v) {
    sum_ += (std::uint64_t{v} - get(cur_.data(), p)) * keys_[p];
    if (width_ == 1) {
      if (v > 255) {
        widen();
      } else {
        cur_[p] = static_cast<std::uint8_t>(v);
        return;
      }
    }
    std::memcpy(&cur_[std::size_t{p} * 4], &v, 4);
  }

  // The key of place p (a transition's hash change is sum of change(p) * key(p)).
  std::uint64_t key(PlaceId p) const { return keys_[p]; }
  // Brings the table slot of the current marking changed by hash_change into the cache.
  void prefetch(std::uint64_t hash_change) const {
    __builtin_prefetch(&table_[question_mix(sum_ + hash_change) & (table_.size() - 1)]);
  }

  bool contains_current() const {
    const std::size_t bytes = cur_.size();
    const std::uint64_t h = question_mix(sum_);
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = h & mask;; i = (i + 1) & mask) {
      const std::uint64_t e = table_[i];
      if (e == kEmptySlot) return false;
      if ((e >> 32) == (h >> 32) && std::memcmp(&arena_[(e & 0xffffffffu) * bytes], cur_.data(), bytes) == 0) {
        return true;
      }
    }
  }

  // Adds the current marking when absent. Returns whether it was new.
  bool insert_current() {
    if ((count_ + 1) * 2 > table_.size()) rehash(table_.size() * 2);
    const std::size_t bytes = cur_.size();
    const std::uint64_t h = question_mix(sum_);
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = h & mask;; i = (i + 1) & mask) {
      const std::uint64_t e = table_[i];
      if (e == kEmptySlot) {
        table_[i] = (h & 0xffffffff00000000ULL) | count_++;
        arena_.insert(arena_.end(), cur_.begin(), cur_.end());
        return true;
      }
      if ((e >> 32) == (h >> 32) && std::memcmp(&arena_[(e & 0xffffffffu) * bytes], cur_.data(), bytes) == 0) {
        return false;
      }
    }
  }

 private:
  static constexpr std::uint64_t kEmptySlot = ~0ULL;

  std::uint64_t get(const std::uint8_t* m, PlaceId p) const {
    if (width_ == 1) return m[p];
    std::uint32_t v;
    std::memcpy(&v, m + std::size_t{p} * 4, 4);
    return v;
  }
  std::uint64_t hash_of(const std::uint8_t* m) const {
    std::uint64_t sum = 0;
    for (PlaceId p = 0; p < places_; ++p) sum += get(m, p) * keys_[p];
    return sum;
  }
  static std::vector<std::uint8_t> wide(const std::vector<std::uint8_t>& narrow) {
    std::vector<std::uint8_t> out(narrow.size() * 4);
    for (std::size_t i = 0; i < narrow.size(); ++i) {
      const std::uint32_t v = narrow[i];
      std::memcpy(&out[i * 4], &v, 4);
    }
    return out;
  }
  void widen() {
    arena_ = wide(arena_);
    cur_ = wide(cur_);
    width_ = 4;
    rehash(table_.size());
  }
  void rehash(std::size_t slots) {
    table_.assign(slots, kEmptySlot);
    const std::size_t bytes = cur_.size();
    const std::size_t mask = slots - 1;
    for (std::uint64_t k = 0; k < count_; ++k) {
      const std::uint64_t h = question_mix(hash_of(&arena_[k * bytes]));
      std::size_t i = h & mask;
      while (table_[i] != kEmptySlot) i = (i + 1) & mask;
      table_[i] = (h & 0xffffffff00000000ULL) | k;
    }
  }

  std::size_t places_;
  std::size_t width_ = 1;
  std::vector<std::uint8_t> arena_;
  std::vector<std::uint64_t> table_;
  std::vector<std::uint8_t> cur_;
  std::vector<std::uint64_t> keys_;
  std::uint64_t sum_ = 0;  // the current marking's
  std::uint64_t count_ = 0;
};

}  // namespace strata::petri::question_detail
