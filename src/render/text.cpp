#include "render/text.h"

#include <stb_truetype.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "render/assets.h"

namespace cmcsurf {

namespace {

const stbtt_fontinfo& font() {
  static const stbtt_fontinfo info = [] {
    stbtt_fontinfo f;
    const auto* data = reinterpret_cast<const unsigned char*>(font_ttf().data());
    if (font_ttf().empty() || !stbtt_InitFont(&f, data, stbtt_GetFontOffsetForIndex(data, 0)))
      throw std::logic_error("the built-in font does not load (cmake/assets.cmake)");
    return f;
  }();
  return info;
}

// Code points of UTF-8 text; a malformed byte reads as '?'.
std::vector<int> code_points(std::string_view s) {
  std::vector<int> out;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = s[i];
    int n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : -1;
    if (n < 0 || i + n >= s.size() + (n == 0 ? 1 : 0)) {
      out.push_back('?');
      ++i;
      continue;
    }
    int cp = n == 0 ? c : c & (0x3f >> n);
    for (int k = 1; k <= n; ++k) cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3f);
    out.push_back(cp);
    i += n + 1;
  }
  return out;
}

}  // namespace

int text_width(std::string_view utf8, float px) {
  const stbtt_fontinfo& f = font();
  const float scale = stbtt_ScaleForPixelHeight(&f, px);
  const std::vector<int> cps = code_points(utf8);
  float w = 0;
  for (std::size_t i = 0; i < cps.size(); ++i) {
    int advance, lsb;
    stbtt_GetCodepointHMetrics(&f, cps[i], &advance, &lsb);
    w += advance * scale;
    if (i + 1 < cps.size()) w += scale * stbtt_GetCodepointKernAdvance(&f, cps[i], cps[i + 1]);
  }
  return int(std::ceil(w));
}

void draw_text(Image& image, int x, int y, float px, std::string_view utf8, Rgb color,
               Align align) {
  const stbtt_fontinfo& f = font();
  const float scale = stbtt_ScaleForPixelHeight(&f, px);
  if (align != Align::kLeft) {
    const int w = text_width(utf8, px);
    x -= align == Align::kCenter ? w / 2 : w;
  }
  const std::vector<int> cps = code_points(utf8);
  float pen = float(x);
  for (std::size_t i = 0; i < cps.size(); ++i) {
    int advance, lsb;
    stbtt_GetCodepointHMetrics(&f, cps[i], &advance, &lsb);
    const float shift = pen - std::floor(pen);
    int w, h, xoff, yoff;
    unsigned char* bitmap = stbtt_GetCodepointBitmapSubpixel(&f, scale, scale, shift, 0.0f, cps[i],
                                                             &w, &h, &xoff, &yoff);
    if (bitmap) {
      for (int j = 0; j < h; ++j)
        for (int k = 0; k < w; ++k)
          image.blend(int(std::floor(pen)) + xoff + k, y + yoff + j, color,
                      bitmap[j * w + k] / 255.0f);
      stbtt_FreeBitmap(bitmap, nullptr);
    }
    pen += advance * scale;
    if (i + 1 < cps.size()) pen += scale * stbtt_GetCodepointKernAdvance(&f, cps[i], cps[i + 1]);
  }
}

}  // namespace cmcsurf
