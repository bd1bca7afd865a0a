// Deterministic parallel loop of the reference library (it does not link the bake's helpers): each index
// writes only its own result slot.
#pragma once

#include <cstddef>
#include <functional>

namespace probebake::bake::detail {

// body(i) for i in [0, count) on up to `threads` threads (0 = all cores).
void reference_parallel_for(std::size_t count, int threads, const std::function<void(std::size_t)>& body);

} // namespace probebake::bake::detail
