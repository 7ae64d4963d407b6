// PNG files of pictures, by stb_image_write / stb_image (Debian libstb-dev): a well-kept
// encoder and decoder instead of our own deflate code (docs/report.md).
#pragma once

#include <filesystem>
#include <string>

#include "render/image.h"

namespace cmcsurf {

// The PNG bytes of an RGB image (8 bits per channel).
std::string encode_png(const Image& image);
// Writes the PNG atomically (common/atomic_file.h).
void write_png(const std::filesystem::path& path, const Image& image);
// Reads a PNG (any bit depth or colour type, converted to 8-bit RGB, alpha over white).
// Throws std::runtime_error naming the file and stb_image's reason.
Image read_png(const std::filesystem::path& path);

}  // namespace cmcsurf
