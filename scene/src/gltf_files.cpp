// Everything the glTF loader reads besides the scene file goes through here: tinygltf's file-system and
// image callbacks are replaced so that external buffers and images resolve only inside the allowed folders
// (symlinks and "..", checked again on the opened descriptor), never through the working directory or
// shell expansion, and every byte read or decoded is charged to the memory budget first.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>

#include <fmt/core.h>
#include <tiny_gltf.h>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

std::filesystem::path resolve(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::path resolved = std::filesystem::weakly_canonical(path, ec); // symlinks and ".." resolved
  return ec ? std::filesystem::absolute(path, ec).lexically_normal() : resolved;
}

bool is_inside(const std::filesystem::path& path, const std::filesystem::path& root) {
  const auto [root_end, unused] = std::mismatch(root.begin(), root.end(), path.begin(), path.end());
  return root_end == root.end();
}

// The path an open descriptor really names (Linux), or empty when /proc is not mounted.
std::filesystem::path descriptor_path(int fd) {
  std::array<char, 4096> buffer{};
  const std::string link = "/proc/self/fd/" + std::to_string(fd);
  const ssize_t n = ::readlink(link.c_str(), buffer.data(), buffer.size() - 1);
  return n > 0 ? std::filesystem::path(std::string(buffer.data(), std::size_t(n))) : std::filesystem::path();
}

class FileDescriptor {
public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

private:
  int fd_;
};

// tinygltf tries "<base_dir>/<uri>" and then "./<uri>" (the working directory): only the first is ours.
bool is_scene_relative(const std::string& path, const InputPolicy& policy) {
  std::string prefix = policy.base_dir.string();
  if (!prefix.ends_with('/')) prefix += '/';
  return path.starts_with(prefix);
}

bool file_exists(const std::string& path, void* user) {
  const auto& policy = *static_cast<const InputPolicy*>(user);
  std::error_code ec;
  return is_scene_relative(path, policy) && policy.allows(path) && std::filesystem::is_regular_file(path, ec);
}

std::string expand_file_path(const std::string& path, void*) { return path; } // no shell expansion

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto& policy = *static_cast<InputPolicy*>(user);
  // O_NONBLOCK: opening a FIFO swapped in after the existence check must not hang the bake.
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY));
  struct stat info {};
  if (fd.get() < 0 || ::fstat(fd.get(), &info) != 0 || !S_ISREG(info.st_mode)) {
    *err = "not a readable regular file";
    return false;
  }
  const std::filesystem::path opened = descriptor_path(fd.get());
  if (!policy.allows(opened.empty() ? std::filesystem::path(path) : opened)) {
    *err = "resolves outside the scene's folder";
    return false;
  }
  const auto size = static_cast<std::uint64_t>(info.st_size);
  policy.budget->charge(size, policy.ctx, fmt::format("external file '{}'", path));
  out->resize(std::size_t(size));
  std::size_t done = 0;
  while (done < out->size()) {
    const ssize_t n = ::read(fd.get(), out->data() + done, out->size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      *err = "read failed or the file shrank while reading";
      return false;
    }
    done += std::size_t(n);
  }
  policy.files_read.push_back(opened.empty() ? resolve(path) : opened);
  return true;
}

bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  *err = "the loader never writes files";
  return false;
}

bool load_image(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void* user) {
  // tinygltf hands a bufferView image over without checking the view's range against its buffer; those are
  // decoded by decode_buffer_view_images once the model is parsed and the range can be checked.
  if (image->bufferView >= 0) return true;
  return decode_image(image, index, bytes, size, *static_cast<InputPolicy*>(user));
}

} // namespace

bool InputPolicy::allows(const std::filesystem::path& path) const {
  const std::filesystem::path resolved = resolve(path);
  return std::any_of(roots.begin(), roots.end(), [&](const auto& root) { return is_inside(resolved, root); });
}

InputPolicy::InputPolicy(const std::filesystem::path& scene_folder, const std::vector<std::filesystem::path>& allowed,
                         MemoryBudget& memory, const Context& context)
    : base_dir(resolve(scene_folder.empty() ? std::filesystem::path(".") : scene_folder)),
      budget(&memory),
      ctx(context) {
  roots.push_back(base_dir);
  for (const auto& folder : allowed) roots.push_back(resolve(folder));
}

void MemoryBudget::charge(std::uint64_t bytes, const Context& ctx, const std::string& place) {
  if (limit_ == 0) return;
  if (bytes > limit_ - std::min(used_, limit_))
    ctx.fail(place,
             fmt::format("needs more than the memory budget of {} MiB (raise it with --max-memory)", limit_ >> 20));
  used_ += bytes;
}

void configure_parser(tinygltf::TinyGLTF& parser, InputPolicy& policy) {
  parser.SetFsCallbacks({&file_exists, &expand_file_path, &read_whole_file, &refuse_write, &policy});
  parser.SetImageLoader(&load_image, &policy);
}

} // namespace probebake::scene::detail
