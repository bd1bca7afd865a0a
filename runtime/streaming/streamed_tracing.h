// The static tracing tree streamed by cell (issue #15; docs/RUNTIME_INTERNALS.md "Streaming cells:
// internals"). One device buffer, the arena, holds at its start the top level of the file's cell-split tree
// (format 1.5, docs/FORMAT.md section 6.1), the dynamic objects' trees and one null face; behind them the
// resident cells' blocks: each cell's nodes, faces and vertices, renumbered on the host to where the block
// lies. The shaders' three tracing bindings (nodes, faces, vertices) all alias the arena, so one budget
// covers the three sections. A cell that is not resident is reached through a leaf holding the null face
// (three equal vertices, which no ray hits): rays cross its box as empty space.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "streaming/background_cell_reader.h"
#include "streaming/cell_source.h"
#include "core/device.h"
#include "core/pipelines.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/streaming/cell_residency.h"

namespace probebake::runtime::detail {

// Size classes: blocks within 1/kSlotClassWidth of the smallest in their class take the class's largest size
// in the arena, so that the run a dropped block frees fits any block of its class (a world's cells are often
// of a few near-equal sizes: rooms of one kind). Costs at most that fraction of a block.
constexpr std::uint64_t kSlotClassWidth = 32;
std::vector<std::uint64_t> slot_bytes(const std::vector<std::uint64_t>& blocks);

// Best-fit allocation of blocks in a byte range, in units of `unit` bytes, freed blocks merged with their
// neighbours (ties to the lowest offset). Offsets are relative to the range.
class BlockAllocator {
public:
  BlockAllocator(std::uint64_t bytes, std::uint64_t unit);
  // The offset of a block of `bytes` (rounded up to the unit), or -1 when no free run is long enough.
  std::int64_t allocate(std::uint64_t bytes);
  void release(std::uint64_t offset, std::uint64_t bytes);
  std::uint64_t free_bytes() const;
  // After a compaction: [0, used_bytes) in use, the rest one free run.
  void compacted(std::uint64_t used_bytes);

private:
  std::uint64_t unit_, units_;
  std::map<std::uint64_t, std::uint64_t> free_; // offset -> units
};

class StreamedTracing {
public:
  // `volume`: validated, with cell_tracing, its trace nodes, faces and vertices read through `tracing` (during
  // the constructor only); only its global parts are kept (the top level, the dynamic objects' trees), each
  // cell is read from `source` when it loads. `cell_bytes`: the arena's room for cell
  // blocks (the streaming budget); `staging_bytes`: the most one frame copies (at least the largest block);
  // one staging buffer per ring. Throws RuntimeError(unsupported) when the arena would pass
  // maxStorageBufferRange or 2 GiB.
  // `background`: read cells on a thread of their own (background_cell_reader.h).
  StreamedTracing(Device& device, const formats::ProbeVolume& volume, const formats::TracingView& tracing,
                  std::unique_ptr<CellSource> source, std::uint64_t cell_bytes, std::uint64_t staging_bytes,
                  std::uint32_t rings, bool background);

  // Each Cell record's slot in the arena (its block's size class, slot_bytes; 0 without faces), in record
  // order: what the residency policy budgets. `volume` has its tracing split by cell (as the constructor needs).
  static std::vector<streaming::CellFootprint> footprints(const formats::ProbeVolume& volume);
  std::uint64_t largest_block() const { return largest_block_; }
  // The child word that stands for a cell that is out: a leaf of the null face (bvh_trace.glsl).
  std::uint32_t null_leaf() const { return null_leaf_; }

  // Loads record() could not carry out: no free run long enough in a fragmented arena, or (background
  // reads) the cell is not read yet: retry later; or the cell's bytes could not be read or differ from
  // those validated: never retry (the reason).
  struct Missed {
    std::vector<std::size_t> unplaced;
    std::vector<std::size_t> reading;
    std::vector<std::pair<std::size_t, std::string>> refused;
    int compacted = 0; // blocks moved to make one free run (compact())
  };
  // Records `changes` into `cmd` (ring `ring`'s staging is free: its last frame finished): drops turn the
  // word that leads to the cell into the null leaf and free the block; loads read the cell from the source,
  // renumber its block on the host into the staging buffer, copy it into a free block and set the word. The
  // cells of Missed stay out.
  Missed record(VkCommandBuffer cmd, std::uint32_t ring, const streaming::ResidencyChanges& changes);

  VkBuffer trees() const { return trees_.get(); }
  VkBuffer arena() const { return arena_.get(); }
  VkDeviceSize arena_size() const { return arena_.size(); }
  VkDeviceSize trees_size() const { return trees_.size(); }
  // The file's tracing sections (trees, nodes, faces, vertices), as read_back() reports them: read again
  // from the source (from disk for a loaded file).
  formats::ProbeVolume file_tracing() const { return source_->tracing(); }

  // Reads the arena back: every resident cell's block, numbered back, equals the file's bytes and the word
  // leading to it points at it; every other cell's word is the null leaf. `file`: the tracing sections and
  // cell_tracing as file_tracing() gave them (read once for the whole check). The problems found (at most 8).
  std::vector<std::string> verify(const formats::ProbeVolume& file) const;

private:
  struct Layout; // where a cell's nodes, faces and vertices lie in a block
  static std::uint64_t block_bytes(const formats::CellTracing& ranges); // Layout's bytes; 0 without faces
  struct CellPart {
    formats::CellTracing ranges{};
    std::uint64_t block_bytes = 0;                   // what it holds
    std::uint64_t slot_bytes = 0;                    // what it takes in the arena (slot_bytes())
    std::int64_t offset = -1;                        // its block in the arena, -1 when not resident
    bool in_tree_root = false;                       // the word leading to it: trace_trees[0].root, or
    std::uint32_t parent_node = 0, parent_child = 0; // child `parent_child` of top-level node `parent_node`
  };
  void build_global_region(const formats::TracingView& tracing, std::vector<std::byte>& bytes);
  void find_parent_words(const formats::ProbeVolume& volume, const formats::TracingView& tracing);
  std::uint32_t cell_root_word(const CellPart& cell) const; // where its block is now
  void write_block(const CellPart& cell, const formats::CellTracingData& data, std::uint64_t offset,
                   std::byte* out) const;
  void set_word(VkCommandBuffer cmd, const CellPart& cell, std::uint32_t word);
  // Whether placing `loads` in turn finds no free run for one while the free bytes would hold it.
  bool fragmented_for(const std::vector<std::size_t>& loads) const;
  // Slides every resident block down to the arena's start, in offset order (stream_relocate.comp), so that
  // the free bytes are one run. Returns the blocks moved.
  int compact(VkCommandBuffer cmd);
  void relocate(VkCommandBuffer cmd, CellPart& cell, std::uint64_t to);

  Device& device_;
  std::unique_ptr<CellSource> source_;
  std::unique_ptr<BackgroundCellReader> reader_; // after source_, which it reads: stops first
  std::vector<CellPart> cells_;
  std::uint32_t top_nodes_ = 0;
  std::uint32_t dynamic_nodes_ = 0;
  std::int64_t dyn_node_shift_ = 0, dyn_face_shift_ = 0; // the dynamic objects' words, file -> arena
  std::uint32_t null_leaf_ = 0;
  std::uint64_t pool_start_ = 0;
  std::uint64_t largest_block_ = 0;
  std::uint64_t staging_bytes_ = 0;
  BlockAllocator blocks_;
  Buffer arena_;
  Buffer trees_;
  std::vector<Buffer> staging_;
  Buffer scratch_; // one block, for compaction
  PassDescriptorSet relocate_set_;
};

} // namespace probebake::runtime::detail
