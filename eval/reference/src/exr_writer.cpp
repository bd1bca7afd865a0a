// OpenEXR output of irradiance images: 32-bit float R, G, B (half floats would clip bright emitters at
// 65504 and lose precision in error maps). Encoded in memory and written with write_file_atomically, like
// every other output (non-regular targets refused, temporaries removed on signals).
#include <filesystem>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <fmt/core.h>

#include "probebake/eval/reference.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

constexpr const char* kChannels[3] = {"R", "G", "B"};

// Slices of channel c of interleaved RGB floats.
Imf::Slice rgb_slice(std::vector<glm::vec3>& pixels, int width, int c) {
  return Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(&pixels[0][c]), sizeof(glm::vec3),
                    sizeof(glm::vec3) * std::size_t(width));
}

} // namespace

void write_exr(const std::filesystem::path& path, const Image& image) {
  if (image.width < 1 || image.height < 1 ||
      image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
    throw Error(ErrorKind::internal, fmt::format("{}: image size does not match its pixels", path.string()));
  Imf::StdOSStream stream; // encoded in memory, then written through the one atomic writer
  try {
    Imf::Header header(image.width, image.height);
    for (const char* name : kChannels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    std::vector<glm::vec3> pixels = image.pixels; // the frame buffer API takes non-const pointers
    Imf::FrameBuffer frame;
    for (int c = 0; c < 3; ++c) frame.insert(kChannels[c], rgb_slice(pixels, image.width, c));
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw Error(ErrorKind::output, fmt::format("{}: cannot encode OpenEXR: {}", path.string(), e.what()));
  }
  write_file_atomically(path, stream.str());
}

Image read_exr(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    Image image;
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    image.pixels.assign(std::size_t(image.width) * std::size_t(image.height), glm::vec3(0.0f));
    Imf::FrameBuffer frame;
    // The frame buffer is addressed in data-window coordinates: shift the base to pixel (min.x, min.y).
    const std::ptrdiff_t origin = std::ptrdiff_t(window.min.y) * image.width + window.min.x;
    for (int c = 0; c < 3; ++c) {
      char* base = reinterpret_cast<char*>(&image.pixels[0][c]) - origin * std::ptrdiff_t(sizeof(glm::vec3));
      frame.insert(kChannels[c],
                   Imf::Slice(Imf::FLOAT, base, sizeof(glm::vec3), sizeof(glm::vec3) * std::size_t(image.width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
  } catch (const std::exception& e) {
    throw Error(ErrorKind::input, fmt::format("{}: cannot read OpenEXR: {}", path.string(), e.what()));
  }
}

} // namespace probebake::bake
