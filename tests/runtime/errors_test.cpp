// Bad input at the API boundary: every failure is a Status with a message, never a crash or an exception.
#include <fstream>
#include <vector>

#include "probebake/formats/probes_file.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using ErrorsTest = RuntimeTest;

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void expect_refused(const runtime::Result<runtime::Volume>& result, runtime::StatusCode code,
                    const std::string& needle) {
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code, code) << result.status().message;
  EXPECT_NE(result.status().message.find(needle), std::string::npos) << result.status().message;
  std::printf("[refused] %s: %s\n", runtime::to_string(result.status().code), result.status().message.c_str());
}

// Both loads: the whole read, and the streaming load's mapping (formats/cell_file.h).
const runtime::UploadOptions kLoads[] = {{}, {.streaming = {.budget_bytes = 1u << 20}}};

TEST_F(ErrorsTest, MissingFileIsAFileError) {
  const std::string path = temp_path("does-not-exist.probes");
  for (const runtime::UploadOptions& options : kLoads)
    expect_refused(runtime::Volume::load(context(), path, options), runtime::StatusCode::file_error,
                   "does-not-exist.probes");
}

TEST_F(ErrorsTest, GarbageIsAFileError) {
  const std::string path = temp_path("garbage.probes");
  write_bytes(path, std::vector<std::uint8_t>(1000, 0x5a));
  for (const runtime::UploadOptions& options : kLoads)
    expect_refused(runtime::Volume::load(context(), path, options), runtime::StatusCode::file_error, "garbage.probes");
  expect_refused(runtime::Volume::load(context(), ::testing::TempDir()), runtime::StatusCode::file_error,
                 "is a directory");
  expect_refused(runtime::Volume::load(context(), ::testing::TempDir(), kLoads[1]), runtime::StatusCode::file_error,
                 "not a regular file");
}

TEST_F(ErrorsTest, TruncatedFileIsAFileError) {
  const std::vector<std::uint8_t> bytes = formats::write_probes(baked_cornell_octree());
  const std::string path = temp_path("truncated.probes");
  for (std::size_t size : {std::size_t(0), std::size_t(63), bytes.size() / 2, bytes.size() - 1}) {
    write_bytes(path, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + std::ptrdiff_t(size)));
    for (const runtime::UploadOptions& options : kLoads)
      expect_refused(runtime::Volume::load(context(), path, options), runtime::StatusCode::file_error,
                     "truncated.probes");
  }
}

TEST_F(ErrorsTest, InvalidVolumeNamesTheInvariant) {
  formats::ProbeVolume broken = baked_cornell_octree();
  broken.probe_index[0] = 1000000;
  const std::string path = temp_path("invalid.probes");
  formats::write_probes_file(path, broken);
  expect_refused(runtime::Volume::load(context(), path), runtime::StatusCode::invalid_volume, "probe_index_list");
  expect_refused(runtime::Volume::upload(context(), broken), runtime::StatusCode::invalid_volume, "probe_index_list");
}

TEST_F(ErrorsTest, ProbeIndexOfTheWrongSizeIsRefusedEvenWithoutValidation) {
  formats::ProbeVolume broken = baked_cornell_octree();
  broken.probe_index.pop_back();
  expect_refused(runtime::Volume::upload(context(), broken, {.validate = false}), runtime::StatusCode::invalid_volume,
                 "probe_index");
}

TEST_F(ErrorsTest, SectionOverMaxStorageBufferRangeIsUnsupported) {
  const std::uint64_t range = context().device_info().max_storage_buffer_range;
  if (range > (std::uint64_t(1) << 29))
    GTEST_SKIP() << "maxStorageBufferRange " << range << " is too large to exceed here";
  formats::ProbeVolume huge = baked_cornell_octree();
  huge.probes.resize(range / sizeof(gpu::Probe) + 1);
  huge.probe_index.assign(huge.probes.size() + 1, gpu::PROBE_INDEX_END);
  formats::sync_info_counts(huge);
  expect_refused(runtime::Volume::upload(context(), huge, {.validate = false}), runtime::StatusCode::unsupported,
                 "maxStorageBufferRange");
}

TEST_F(ErrorsTest, MismatchedSampleSpansAreAnInvalidArgument) {
  auto volume = runtime::Volume::upload(context(), baked_cornell_octree());
  ASSERT_TRUE(volume.ok());
  const std::vector<glm::vec3> positions(3), normals(2);
  auto result = volume->sample_irradiance(positions, normals);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code, runtime::StatusCode::invalid_argument);
  EXPECT_NE(result.status().message.find("3 positions but 2 normals"), std::string::npos);
}

TEST_F(ErrorsTest, EmptySampleBatchIsFine) {
  auto volume = runtime::Volume::upload(context(), baked_cornell_octree());
  ASSERT_TRUE(volume.ok());
  runtime::SampleStats stats;
  auto result = volume->sample_irradiance({}, {}, &stats);
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result->empty());
  EXPECT_EQ(stats.dispatches, 0u);
}

} // namespace
} // namespace probebake::test

namespace probebake::test {
namespace {

TEST(ContextErrors, NoMatchingDeviceIsNoDevice) {
  runtime::ContextOptions options;
  options.device_name_contains = "no-such-gpu";
  auto context = runtime::Context::create(options);
  ASSERT_FALSE(context.ok());
  EXPECT_EQ(context.status().code, runtime::StatusCode::no_device);
  EXPECT_NE(context.status().message.find("no-such-gpu"), std::string::npos) << context.status().message;
}

} // namespace
} // namespace probebake::test
