// Deterministic parallel loops for every library that runs per-probe or per-sample work (scene, placement, bake, lighting, reference): each index writes only
// its own result slot, so the output does not depend on the thread count or scheduling.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace probebake {

// Runs body(i) for i in [0, count) on up to `threads` threads (0 = all cores).
void parallel_for(std::size_t count, int threads, const std::function<void(std::size_t)>& body);

// Runs `work` inside a one-thread TBB arena. Embree's builders (rtcCommitScene, rtcBuildBVH) run their TBB
// tasks in the caller's arena, so this gives the same tree on every run without Embree's "threads=1"
// device setting, which pins oneTBB's global concurrency, and with it the whole bake, to one thread.
void run_on_one_thread(const std::function<void()>& work);

// While alive, caps every TBB parallel loop of the process (ours, OpenVDB's, Embree's queries) at
// `threads` (0 = no cap): one explicit thread setting for the whole bake.
class ThreadLimit {
public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace probebake
