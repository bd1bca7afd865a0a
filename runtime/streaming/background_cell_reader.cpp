#include "streaming/background_cell_reader.h"

#include <algorithm>
#include <utility>

#include "probebake/formats/error.h"

namespace probebake::runtime::detail {

BackgroundCellReader::BackgroundCellReader(const CellSource& source) : source_(source), thread_([this] { run(); }) {}

BackgroundCellReader::~BackgroundCellReader() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

std::optional<formats::CellTracingData> BackgroundCellReader::take_or_request(std::size_t k) {
  std::unique_lock lock(mutex_);
  if (auto it = done_.find(k); it != done_.end()) {
    Read read = std::move(it->second);
    done_.erase(it);
    if (!read.error.empty()) throw Error(read.kind, read.error); // as the source threw it, on this thread
    return std::move(read.data);
  }
  if (reading_ != k && std::find(queue_.begin(), queue_.end(), k) == queue_.end()) {
    queue_.push_back(k);
    lock.unlock();
    wake_.notify_one();
  }
  return std::nullopt;
}

void BackgroundCellReader::keep_only(std::span<const std::size_t> wanted) {
  const auto is_wanted = [&](std::size_t k) { return std::find(wanted.begin(), wanted.end(), k) != wanted.end(); };
  std::lock_guard lock(mutex_);
  std::erase_if(queue_, [&](std::size_t k) { return !is_wanted(k); });
  std::erase_if(done_, [&](const auto& entry) { return !is_wanted(entry.first); });
}

void BackgroundCellReader::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const std::size_t k = queue_.front();
    queue_.pop_front();
    reading_ = k;
    lock.unlock();
    Read read;
    try {
      read.data = source_.read(k);
    } catch (const Error& e) {
      read.kind = e.kind(), read.error = e.what();
    } catch (const std::exception& e) { // out of memory
      read.kind = ErrorKind::internal, read.error = std::string("reading a cell: ") + e.what();
    }
    lock.lock();
    reading_.reset();
    done_[k] = std::move(read);
  }
}

} // namespace probebake::runtime::detail
