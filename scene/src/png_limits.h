// Checks of a PNG's bytes that stb does not make before it allocates (found by fuzz_scene_loader):
//  - stb grows its IDAT buffer to a chunk's declared length before it reads the chunk: a 38 KB texture that
//    declared a 1.1 GB chunk made it ask for 2 GB. Every chunk up to IEND must lie within the bytes.
//  - stb inflates the pixel data into a buffer it doubles as the stream demands: a deflate bomb (about 1000:1)
//    takes a thousand times the PNG's bytes whatever the header says. The data must inflate to no more than
//    the header's image needs; it is inflated once here, through a fixed 64 KiB window, to count.
#pragma once

#include <cstddef>
#include <string>

namespace probebake::scene::detail {

// True for bytes that are not a PNG, and for a PNG that passes both checks (anything else wrong with it is
// stb's to report); false with `why` set ("corrupt PNG: ...") otherwise.
bool png_within_limits(const unsigned char* bytes, std::size_t size, std::string& why);

} // namespace probebake::scene::detail
