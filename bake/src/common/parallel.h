// Deterministic parallel loops for every bake library (bake, lighting, reference): each index writes only
// its own result slot, so the output does not depend on the thread count or scheduling.
#pragma once

#include <cstddef>
#include <functional>

namespace probebake::bake::detail {

// Runs body(i) for i in [0, count) on up to `threads` threads (0 = all cores).
void parallel_for(std::size_t count, int threads, const std::function<void(std::size_t)>& body);

} // namespace probebake::bake::detail
