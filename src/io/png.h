// PNG files of pictures: written with zlib's deflate, read by stb_image (Debian libstb-dev),
// whose encoder is kept as the twin (docs/report.md).
#pragma once

#include <filesystem>
#include <string>

#include "render/image.h"

namespace cmcsurf {

// The PNG bytes of an RGB image (8 bits per channel): every row Paeth-filtered, deflated by
// zlib at level 1 (3-4 times faster than stb's encoder at level 9, and smaller).
std::string encode_png(const Image& image);
// The same pixels by stb_image_write at level 9 (what encode_png wrote before): its twin.
std::string encode_png_ref(const Image& image);
// Writes the PNG atomically (common/atomic_file.h).
void write_png(const std::filesystem::path& path, const Image& image);
// Reads a PNG (any bit depth or colour type, converted to 8-bit RGB, alpha over white).
// Throws std::runtime_error naming the file and stb_image's reason.
Image read_png(const std::filesystem::path& path);

}  // namespace cmcsurf
