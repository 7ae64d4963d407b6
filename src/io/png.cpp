#include "io/png.h"

#include <stb_image.h>
#include <stb_image_write.h>
#include <zlib.h>

#include <fmt/format.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/input_file.h"

namespace cmcsurf {

namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(char((v >> shift) & 0xff));
}

// A chunk: length, type, data and the CRC-32 of type and data (PNG specification, 5.3).
void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32(out, std::uint32_t(data.size()));
  const std::size_t start = out.size();
  out.append(type, 4);
  out += data;
  const auto* bytes = reinterpret_cast<const Bytef*>(out.data() + start);
  put_u32(out, std::uint32_t(crc32(0L, bytes, uInt(out.size() - start))));
}

// The Paeth predictor of the PNG specification (9.4).
inline std::uint8_t paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return std::uint8_t(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

}  // namespace

std::string encode_png(const Image& image) {
  const int w = image.width, h = image.height;
  const std::size_t row = std::size_t(w) * 3;
  if (w <= 0 || h <= 0 || image.rgb.size() != row * std::size_t(h))
    throw std::runtime_error(fmt::format("PNG encoding of a {} x {} picture failed", w, h));
  // Each row: filter type 4 (Paeth), then the differences to the predictor (a left, b up,
  // c up-left; 0 outside the picture).
  std::string filtered(std::size_t(h) * (row + 1), '\0');
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* p = image.rgb.data() + std::size_t(y) * row;
    const std::uint8_t* up = y > 0 ? p - row : nullptr;
    char* out = &filtered[std::size_t(y) * (row + 1)];
    out[0] = 4;
    for (std::size_t x = 0; x < row; ++x) {
      const int a = x >= 3 ? p[x - 3] : 0, b = up ? up[x] : 0, c = up && x >= 3 ? up[x - 3] : 0;
      out[1 + x] = char(std::uint8_t(p[x] - paeth(a, b, c)));
    }
  }
  uLongf size = compressBound(uLong(filtered.size()));
  std::string deflated(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(deflated.data()), &size,
                reinterpret_cast<const Bytef*>(filtered.data()), uLong(filtered.size()),
                1) != Z_OK)
    throw std::runtime_error(fmt::format("PNG encoding of a {} x {} picture failed", w, h));
  deflated.resize(size);
  std::string header;
  put_u32(header, std::uint32_t(w));
  put_u32(header, std::uint32_t(h));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, filters, no interlace
  std::string out("\x89PNG\r\n\x1a\n", 8);
  put_chunk(out, "IHDR", header);
  put_chunk(out, "IDAT", deflated);
  put_chunk(out, "IEND", "");
  return out;
}

std::string encode_png_ref(const Image& image) {
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
