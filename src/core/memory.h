#pragma once
// The process's memory as the kernel counts it, for the analysis limits
// (`strata verify --max-memory`): a limit on what a step may still allocate
// is the limit minus what the process already holds.
#include <cstddef>

namespace strata::core {

// Resident bytes now (Linux: /proc/self/statm); 0 when not known.
std::size_t resident_bytes();

// What a step may allocate under a limit on the whole process's resident
// memory: limit - resident_bytes(), at least 1 byte (a step that must stop
// at once); 0 (no limit) when limit is 0.
std::size_t memory_left(std::size_t limit_bytes);

}  // namespace strata::core
