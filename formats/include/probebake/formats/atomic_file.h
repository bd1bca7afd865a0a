// Atomic file output for every file probebake writes: the bytes go to a temporary file
// "<target>.tmp.<pid>.<n>" in the target's folder, are flushed to disk (fsync), and the temporary file is
// renamed over the target (then the folder is flushed too), so a reader never sees a half-written file.
// On failure the temporary file is removed and Error(output) thrown with "<path>: <reason>".
//
// Refusals (Error(output), exit code 3):
// - an existing target that is not a regular file (a directory, a device such as /dev/null, a FIFO, a
//   socket, or a symbolic link to one): replacing it by a regular file would break whatever it was;
// - (check_output_path) an output that is one of the inputs, however spelled: the same path, "a/../b",
//   a symbolic link or a hard link to it.
// A symbolic link to a regular file (or a dangling one) is written through: the link stays and the file
// it points to is replaced, atomically, in that file's folder; as a shell's `>` would.
//
// Signals: while a temporary file exists its path is in a fixed-size, async-signal-safe registry; the
// first write installs handlers for SIGINT, SIGTERM and SIGHUP (only where the disposition is still the
// default, so an ignored SIGHUP under nohup stays ignored) that remove the registered temporaries and
// re-raise the signal with the default action, so the exit status still says "killed by signal N". A
// kill at any moment therefore leaves the old target or the complete new one. SIGKILL cannot be caught:
// the target is still old or new (rename is atomic) but a temporary may remain; the next write of the
// same target removes temporaries of that target whose writer is gone (no such process, no lock held).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

namespace probebake {

void write_file_atomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

// Checks, before any work, that `output` can be written: it is not one of `inputs` (compared as files:
// symbolic and hard links included; inputs that do not exist are skipped), it is not an existing
// non-regular file, and its folder exists. Error(output) "<output>: <reason>" otherwise.
void check_output_path(const std::filesystem::path& output, std::span<const std::filesystem::path> inputs);

// For tests: called at each step of write_file_atomically with the step's name: "registered" (before
// the temporary file is created), "created", "chunk" (after each MiB written), "synced" (flushed to
// disk), "renamed" (before the registry forgets the temporary), "done". A test stops the writer there to
// kill it at every moment. nullptr (the default) calls nothing.
using AtomicWriteTestHook = void (*)(std::string_view step);
void set_atomic_write_test_hook(AtomicWriteTestHook hook);

} // namespace probebake
