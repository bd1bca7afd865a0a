// Reads streamed cells on a thread of its own (StreamingOptions::read_in_background), so that recording a
// frame never waits for the disk: a frame takes the cells already read and asks for the others, which
// arrive in a later frame. What it holds is bounded by one frame's requests: keep_only() forgets the rest.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>

#include "streaming/cell_source.h"
#include "probebake/formats/error.h"

namespace probebake::runtime::detail {

class BackgroundCellReader {
public:
  explicit BackgroundCellReader(const CellSource& source);
  ~BackgroundCellReader(); // a read in progress finishes first
  BackgroundCellReader(const BackgroundCellReader&) = delete;
  BackgroundCellReader& operator=(const BackgroundCellReader&) = delete;

  // Cell k's bytes when read, taken out (an error reading them is rethrown here, of the kind the source
  // threw); otherwise asks for it, unless it is already asked for, and returns nullopt.
  std::optional<formats::CellTracingData> take_or_request(std::size_t k);
  // Forgets every cell not in `wanted`: queued ones are not read, read ones are dropped.
  void keep_only(std::span<const std::size_t> wanted);

private:
  struct Read {
    formats::CellTracingData data;
    ErrorKind kind = ErrorKind::input;
    std::string error; // the error's message, or empty
  };
  void run();

  const CellSource& source_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::size_t> queue_;
  std::map<std::size_t, Read> done_;
  std::optional<std::size_t> reading_; // the cell being read now
  bool stop_ = false;
  std::thread thread_; // last: starts once the members above exist
};

} // namespace probebake::runtime::detail
