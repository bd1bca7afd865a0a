#include "probebake/common/parallel.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace probebake {

namespace {

// More threads than cores gain nothing, and TBB crashes when asked for tens of thousands of them.
int clamp_threads(int threads) { return std::min(threads, tbb::info::default_concurrency()); }

} // namespace

void parallel_for(std::size_t count, int threads, const std::function<void(std::size_t)>& body) {
  tbb::task_arena arena(threads > 0 ? clamp_threads(threads) : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
    });
  });
}

struct ThreadLimit::Impl {
  explicit Impl(int threads)
      : control(tbb::global_control::max_allowed_parallelism, std::size_t(clamp_threads(threads))) {}
  tbb::global_control control;
};

ThreadLimit::ThreadLimit(int threads) : impl_(threads > 0 ? std::make_unique<Impl>(threads) : nullptr) {}

ThreadLimit::~ThreadLimit() = default;

void run_on_one_thread(const std::function<void()>& work) {
  tbb::task_arena arena(1);
  arena.execute(work);
}

} // namespace probebake
