// Cell streaming inside a frame (issue #15; docs/RUNTIME.md "Streaming cells"): the residency policy
// (probebake_streaming) decides around the host's camera, the streamed tracing arena applies the drops and
// loads, and the light update is told which probe slots to light (the resident cells') and which to trace
// afresh (the cells that just arrived). With the memory update, which writes the light list itself, only
// the tracing streams and arrivals start the retries of unresolved probes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan_core.h>

#include "core/commands.h"
#include "light_update/light_update_pass.h"
#include "streaming/streamed_tracing.h"
#include "probebake/runtime/vocabulary.h"
#include "probebake/streaming/cell_residency.h"

namespace probebake::runtime::detail {

class CellStreaming {
public:
  // `source`: where cells are read when they load (cell_source.h); `tracing`: the volume's trace nodes, faces
  // and vertices, read during the constructor only. `lists_probes`: the host writes the light list (the
  // resident cells' probes, in record slots it hands out); false with the memory update.
  CellStreaming(Device& device, const formats::ProbeVolume& volume, const formats::TracingView& tracing,
                std::unique_ptr<CellSource> source, const StreamingOptions& options, std::uint32_t rings,
                bool lists_probes = true);
  // How the light update finds a probe's records (light_update_pass.h).
  RecordSlots record_slots() const {
    return lists_probes_ ? RecordSlots{RecordSlots::Kind::handed_out, record_slot_count_}
                         : RecordSlots{RecordSlots::Kind::own_marked, 0};
  }

  StreamedTracing& tracing() { return tracing_; }
  const StreamedTracing& tracing() const { return tracing_; }
  void set_camera(glm::vec3 position, float radius) { camera_ = position, radius_ = radius, moved_ = true; }
  void set_budget(std::uint64_t bytes) { residency_.set_budget(bytes), moved_ = true; }
  std::uint64_t max_budget() const { return max_budget_; }
  std::vector<int> resident_cells() const;
  // Why each refused cell was refused, in the order it happened.
  const std::vector<std::string>& refusals() const { return refusals_; }
  // Without lists_probes (the memory update): the cells that dropped (grid index) or arrived (their cell
  // record with gpu::MEMORY_CELL_ARRIVED) since the last call, for the probe tree to follow (the upload
  // holds every cell collapsed: streamed_tree.h).
  std::vector<std::uint32_t> take_tree_changes();

  // Records this frame's residency changes (between the timer slot's timestamps when there are any) and
  // the light list; ring `ring`'s staging buffer must be free.
  // `timed`: set when the slot's timestamps were written.
  StreamStats record(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot, std::uint32_t ring,
                     LightUpdatePass& light, bool& timed);

private:
  StreamedTracing tracing_;
  streaming::CellResidency residency_;
  // Applies the residency changes to the lit cells and admits waiting probes within max_joining_probes and
  // the free record slots; returns whether the light list changed, with the probe ranges to trace afresh
  // and those whose record slots changed.
  bool update_lit_cells(const streaming::ResidencyChanges& changes, std::vector<formats::CellRange>& retrace,
                        std::vector<formats::CellRange>& reassigned, StreamStats& stats);
  // StreamingOptions::light_reach: the cells (with faces) within `reach` metres of each cell.
  void find_cells_within_reach(const formats::ProbeVolume& volume, float reach);
  // Resident, and so is every cell within light_reach: its probes may be lit.
  bool lightable(std::size_t k) const;

  std::vector<formats::CellRange> probe_ranges_;  // per Cell record: its probe slots
  std::vector<std::uint32_t> lit_;                // per Cell record: its first lit_[k] probes are in the light list
  std::vector<std::size_t> joining_;              // lightable cells with probes not lit yet, in arrival order
  std::vector<std::uint8_t> queued_;              // per Cell record: in joining_
  std::vector<std::vector<std::uint32_t>> reach_; // per Cell record: the cells within light_reach (with faces)
  std::vector<std::size_t> reach_cells_;          // the records with probes and a non-empty reach_
  std::vector<std::int32_t> record_of_probe_;     // per probe slot: its record slot, -1 when not lit
  std::vector<std::int32_t> free_records_;        // record slots not handed out (taken from the back)
  std::vector<std::string> refusals_;
  std::vector<std::uint32_t> tree_changes_; // take_tree_changes()
  std::uint32_t record_slot_count_ = 0;
  int max_joining_probes_ = 0;
  std::uint64_t max_budget_ = 0;
  bool lists_probes_ = true;
  glm::vec3 camera_{0.0f};
  float radius_ = -1.0f; // no camera yet: no cell wanted
  bool moved_ = false;   // camera or budget changed since the last record (a still camera may still have waiting cells)
  bool pending_ = false; // cells wait or failed: update again next frame
};

} // namespace probebake::runtime::detail
