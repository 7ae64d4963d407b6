#include "io/png.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/input_file.h"

namespace cmcsurf {

std::string encode_png(const Image& image) {
  stbi_write_png_compression_level = 9;
  std::string out;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
  };
  if (!stbi_write_png_to_func(append, &out, image.width, image.height, 3, image.rgb.data(),
                              image.width * 3))
    throw std::runtime_error(
        fmt::format("PNG encoding of a {} x {} picture failed", image.width, image.height));
  return out;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  write_file_atomic(path, encode_png(image));
}

Image read_png(const std::filesystem::path& path) {
  require_regular_file(path, "PNG file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read '{}'", path.string()));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  const std::string data = bytes.str();
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels =
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(data.data()), int(data.size()), &w,
                            &h, &channels, 4);
  if (!pixels)
    throw std::runtime_error(
        fmt::format("'{}' is not a readable PNG: {}", path.string(), stbi_failure_reason()));
  Image image(w, h);
  for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
    const float a = pixels[4 * i + 3] / 255.0f;
    for (int c = 0; c < 3; ++c)
      image.rgb[3 * i + c] = to_byte(a * pixels[4 * i + c] / 255.0f + (1.0f - a));
  }
  stbi_image_free(pixels);
  return image;
}

}  // namespace cmcsurf
