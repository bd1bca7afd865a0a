// Deterministic parallel loop of the lighting stage: body(i) writes only slot i, so results do not
// depend on the thread count. (Own copy: probebake_lighting sits below probebake_bake.)
#pragma once

#include <cstddef>
#include <functional>

namespace probebake::bake::lighting_detail {

// Runs body(i) for i in [0, count) on up to `threads` threads (0 = all cores).
void parallel_for(std::size_t count, int threads, const std::function<void(std::size_t)>& body);

} // namespace probebake::bake::lighting_detail
