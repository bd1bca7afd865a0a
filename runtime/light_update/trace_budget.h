// FrameLimits::frame_ms for the load trace: how many probe slots the next frame's load window traces, from
// the GPU time of frames that finished, corrected with every measured frame. A slot the window adds costs its
// trace once and its gather from then on (an untraced probe is not gathered), so the window is the spare time
// (the budget less the other passes' last time) over the trace and gather time of one slot. Decides on the host from counts; the counts it chose are in
// LightStats::load_window, and replaying them as FrameLimits::max_traced_probes reproduces the run bit for bit.
#pragma once

#include <cstdint>

#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

class TraceBudget {
public:
  // Slots for the next load window within `frame_ms` (> 0), of `untraced` slots left: at least 1, so that
  // the load always ends; kFirstWindow until a frame with a load window was measured.
  std::uint32_t next_window(float frame_ms, std::uint32_t untraced) const;
  // A finished frame's statistics: its light_trace time per load-window slot, light_gather time per traced
  // slot and the other passes' time.
  // Frames without a load window or without timestamps change nothing.
  void observe(const FrameStats& stats);

  // One probe: nothing is known of the device yet, and on a slow one (lavapipe: 14 ms a probe of the Cornell
  // grid) even that is a long frame; the first measured frame sets the pace.
  static constexpr std::uint32_t kFirstWindow = 1;

private:
  double trace_ms_per_slot_ = 0.0;  // 0: not measured yet
  double gather_ms_per_slot_ = 0.0; // light_gather over the slots traced so far
  double other_ms_ = 0.0;           // the frame's passes other than light_trace
};

} // namespace probebake::runtime::detail
