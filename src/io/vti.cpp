#include "io/vti.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <span>
#include <streambuf>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>

#include <fmt/core.h>

#include "common/atomic_file.h"
#include "common/input_file.h"
#include "common/text_encoding.h"

namespace cmcsurf {

static_assert(std::endian::native == std::endian::little,
              "VTI I/O copies raw little-endian bytes; a big-endian host needs byte swapping");

namespace {

// ---- shared helpers ---------------------------------------------------------

std::string xml_unescape(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '&') {
      out += s[i];
      continue;
    }
    const std::size_t semi = s.find(';', i);
    const std::string_view ent =
        semi == std::string_view::npos ? "" : s.substr(i + 1, semi - i - 1);
    char c = 0;
    if (ent == "amp") c = '&';
    else if (ent == "lt") c = '<';
    else if (ent == "gt") c = '>';
    else if (ent == "quot") c = '"';
    else if (ent == "apos") c = '\'';
    else if (ent.size() > 1 && ent[0] == '#') {
      const bool hex = ent[1] == 'x' || ent[1] == 'X';
      unsigned code = 0;
      const char* first = ent.data() + (hex ? 2 : 1);
      const char* last = ent.data() + ent.size();
      const auto [p, ec] = std::from_chars(first, last, code, hex ? 16 : 10);
      if (ec == std::errc() && p == last && code > 0 && code < 0x80) c = static_cast<char>(code);
    }
    if (c == 0) {  // unknown entity: keep verbatim
      out += '&';
      continue;
    }
    out += c;
    i = semi;
  }
  return out;
}

// Metadata lines "key=value" inside the XML comment: backslash escapes keep
// them on one line, keep "--" out of the comment and '=' out of keys.
std::string comment_escape(std::string_view s, bool is_key) {
  std::string out;
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (u < 0x20 || u == 0x7f) out += fmt::format("\\x{:02x}", u);
    else if (c == '=' && is_key) out += "\\=";
    else if (c == '-' && !out.empty() && out.back() == '-') out += "\\-";
    else out += c;
  }
  return out;
}

// Parses one metadata line; false if it has no unescaped '='.
bool parse_metadata_line(std::string_view line, std::string* key, std::string* value) {
  std::string cur;
  bool have_key = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (c == '=' && !have_key) {
      *key = std::move(cur);
      cur.clear();
      have_key = true;
      continue;
    }
    if (c == '\\' && i + 1 < line.size()) {
      const char e = line[++i];
      if (e == 'n') c = '\n';
      else if (e == 'r') c = '\r';
      else if (e == 't') c = '\t';
      else if (e == 'x' && i + 2 < line.size()) {
        unsigned code = 0;
        std::from_chars(line.data() + i + 1, line.data() + i + 3, code, 16);
        c = static_cast<char>(code);
        i += 2;
      } else c = e;  // '\\', '=', '-'
    }
    cur += c;
  }
  if (!have_key) return false;
  *value = std::move(cur);
  return true;
}

std::optional<double> parse_finite_number(std::string_view s) {
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// ---- writer -----------------------------------------------------------------

// The cell values at the points of the file: the N^3 cells plus the periodic wrap, (N+1)^3
// points, point i on each axis holding cell i mod N, so that VTK's point grid covers the whole
// unit cell. A block of nx x ny x nz cells gives (nx+1)(ny+1)(nz+1) points, the last on each
// axis from its high ghosts (the next block's first cells, or the wrap).
template <class T>
void write_values(std::ostream& os, const Field& f, std::vector<T>& slab) {
  const bool whole = f.whole();
  const int mx = f.nx() + 1, my = f.ny() + 1, mz = f.nz() + 1;
  slab.resize(std::size_t(mx) * my);
  for (int k = 0; k < mz; ++k) {
    for (int j = 0; j < my; ++j) {
      const double* row =
          f.data() + (whole ? f.index(0, j % f.ny(), k % f.nz()) : f.index(0, j, k));
      T* dst = slab.data() + std::size_t(j) * mx;
      for (int i = 0; i < mx - 1; ++i) dst[i] = static_cast<T>(row[i]);
      dst[mx - 1] = static_cast<T>(row[whole ? 0 : mx - 1]);
    }
    os.write(reinterpret_cast<const char*>(slab.data()),
             static_cast<std::streamsize>(slab.size() * sizeof(T)));
  }
}

// The point extent "x0 x1 y0 y1 z0 z1" of a field's block (with the wrap or the next block's
// first points): "0 N 0 N 0 N" for the whole grid.
std::string point_extent(const Field& f) {
  const auto& o = f.offset();
  return fmt::format("{} {} {} {} {} {}", o[0], o[0] + f.nx(), o[1], o[1] + f.ny(), o[2],
                     o[2] + f.nz());
}

// The XML declaration and the cmcsurf comment: layout=periodic, then the metadata.
std::string comment_head(const std::map<std::string, std::string>& metadata) {
  std::string head = "<?xml version=\"1.0\"?>\n<!-- cmcsurf\n";
  head += std::string(kVtiLayoutKey) + "=" + kVtiPeriodicLayout + "\n";
  for (const auto& [key, value] : metadata)
    if (key != kVtiLayoutKey)
      head += comment_escape(key, true) + "=" + comment_escape(value, false) + "\n";
  head += "-->\n";
  return head;
}

std::string origin_spacing(int n) {
  const double h = 1.0 / n;
  return fmt::format("Origin=\"{0:.17g} {0:.17g} {0:.17g}\" Spacing=\"{1:.17g} {1:.17g} {1:.17g}\"",
                     h / 2, h);
}

// ---- reader: a small scanner for the headers of our own formats -------------

struct ArrayInfo {
  std::string name;
  bool float32;
  std::uint64_t offset;
};

struct Tag {
  std::string name;
  std::map<std::string, std::string> attrs;
  bool closing = false;
  bool self_closing = false;
};

using Extent = std::array<long long, 6>;

std::string extent_text(const Extent& e) {
  return fmt::format("{} {} {} {} {} {}", e[0], e[1], e[2], e[3], e[4], e[5]);
}

// Six integers "x0 x1 y0 y1 z0 z1".
std::optional<Extent> parse_extent(const std::string& s) {
  Extent e{};
  const char* p = s.data();
  const char* last = s.data() + s.size();
  for (auto& v : e) {
    while (p < last && std::isspace(static_cast<unsigned char>(*p))) ++p;
    const auto [q, ec] = std::from_chars(p, last, v);
    if (ec != std::errc()) return std::nullopt;
    p = q;
  }
  while (p < last && std::isspace(static_cast<unsigned char>(*p))) ++p;
  if (p != last) return std::nullopt;
  return e;
}

// The XML of a .vti or .pvti header: tags and attributes, the element stack, the cmcsurf
// comment (metadata); a subclass takes the elements.
class XmlHeaderScanner {
 public:
  XmlHeaderScanner(const char* kind, const char* root_type, std::string source)
      : kind_(kind), root_type_(root_type), source_(std::move(source)) {}
  virtual ~XmlHeaderScanner() = default;

  [[noreturn]] void fail(const std::string& msg) const {
    throw std::runtime_error(fmt::format("cannot read {} file '{}': {}", kind_, source_, msg));
  }

  // Parses text from the start; true once the header is complete (a .vti: the '_' marker
  // after <AppendedData>; a .pvti: the root element closed), false if more text is needed.
  // Throws on unsupported content; at_eof turns "need more" into an error.
  bool parse(std::string_view text, bool at_eof) {
    stack_.clear();
    metadata_.clear();
    in_appended_ = false;
    root_closed_ = false;
    data_start_ = 0;
    reset();
    std::size_t pos = 0;
    while (true) {
      if (in_appended_) {
        while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
        if (pos >= text.size())
          return need_more(at_eof, "the file ends before the '_' marker of <AppendedData>");
        if (text[pos] != '_')
          fail(fmt::format("expected the '_' marker at the start of <AppendedData>, found '{}'",
                           text[pos]));
        data_start_ = pos + 1;
        return true;
      }
      const std::size_t lt = text.find('<', pos);
      if (lt == std::string_view::npos) {
        if (complete()) return true;
        return need_more(at_eof, missing_end());
      }
      const std::string_view rest = text.substr(lt);
      if (rest.starts_with("<!--")) {
        const std::size_t end = text.find("-->", lt + 4);
        if (end == std::string_view::npos)
          return need_more(at_eof, "the file ends inside an XML comment");
        on_comment(text.substr(lt + 4, end - lt - 4));
        pos = end + 3;
        continue;
      }
      if (rest.starts_with("<?") || rest.starts_with("<!")) {
        const std::size_t end = text.find('>', lt);
        if (end == std::string_view::npos)
          return need_more(at_eof, "the file ends inside the XML header");
        pos = end + 1;
        continue;
      }
      Tag tag;
      const std::size_t end = scan_tag(text, lt, &tag);
      if (end == std::string_view::npos)
        return need_more(at_eof, "the file ends inside the XML header");
      pos = end;
      on_tag(tag);
    }
  }

  std::size_t data_start() const { return data_start_; }
  std::map<std::string, std::string>& metadata() { return metadata_; }

 protected:
  virtual void reset() = 0;
  virtual void on_element(const Tag& tag, const std::string& parent) = 0;
  // Whether the header is complete without an appended section (a .pvti once its root closed).
  virtual bool complete() const { return false; }
  virtual const char* missing_end() const = 0;

  static const std::string* attr(const Tag& tag, const char* name) {
    const auto it = tag.attrs.find(name);
    return it == tag.attrs.end() ? nullptr : &it->second;
  }

  // The root's type, compressor and byte order; returns the header_type's bytes (4 or 8).
  int check_vtkfile(const Tag& tag) const {
    const std::string* type = attr(tag, "type");
    if (!type || *type != root_type_)
      fail(fmt::format("VTKFile type=\"{}\" is not supported; only type=\"{}\"",
                       type ? *type : "(missing)", root_type_));
    if (const std::string* c = attr(tag, "compressor"); c && !c->empty())
      fail(fmt::format("compressed data (compressor=\"{}\") is not supported; only uncompressed "
                       "raw appended data (as written by cmcsurf)", *c));
    const std::string* order = attr(tag, "byte_order");
    if (!order || *order != "LittleEndian")
      fail(fmt::format("byte_order=\"{}\" is not supported; only byte_order=\"LittleEndian\"",
                       order ? *order : "(missing)"));
    const std::string* ht = attr(tag, "header_type");
    if (!ht || *ht == "UInt32") return 4;  // VTK's default when absent
    if (*ht == "UInt64") return 8;
    fail(fmt::format("header_type=\"{}\" is not supported; only UInt32 or UInt64", *ht));
  }

  void start_appended() { in_appended_ = true; }

 private:
  bool need_more(bool at_eof, const char* what) const {
    if (at_eof) fail(fmt::format("{} (file truncated or not a VTK XML file?)", what));
    return false;
  }

  // Returns the position after '>', or npos if the tag is incomplete.
  std::size_t scan_tag(std::string_view t, std::size_t lt, Tag* tag) const {
    auto is_space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    auto is_name_end = [&](char c) { return is_space(c) || c == '>' || c == '/' || c == '='; };
    std::size_t p = lt + 1;
    if (p < t.size() && t[p] == '/') {
      tag->closing = true;
      ++p;
    }
    const std::size_t name_begin = p;
    while (p < t.size() && !is_name_end(t[p])) ++p;
    tag->name = std::string(t.substr(name_begin, p - name_begin));
    while (true) {
      while (p < t.size() && is_space(t[p])) ++p;
      if (p >= t.size()) return std::string_view::npos;
      if (t[p] == '>') return p + 1;
      if (t[p] == '/') {
        if (p + 1 >= t.size()) return std::string_view::npos;
        if (t[p + 1] != '>') fail(fmt::format("malformed XML tag <{}> near byte {}", tag->name, p));
        tag->self_closing = true;
        return p + 2;
      }
      const std::size_t attr_begin = p;
      while (p < t.size() && !is_name_end(t[p])) ++p;
      const std::string attr(t.substr(attr_begin, p - attr_begin));
      while (p < t.size() && is_space(t[p])) ++p;
      if (p >= t.size()) return std::string_view::npos;
      if (t[p] != '=' || attr.empty())
        fail(fmt::format("malformed attribute in XML tag <{}> near byte {}", tag->name, p));
      ++p;
      while (p < t.size() && is_space(t[p])) ++p;
      if (p >= t.size()) return std::string_view::npos;
      const char quote = t[p];
      if (quote != '"' && quote != '\'')
        fail(
            fmt::format("unquoted value of attribute {} in <{}> near byte {}", attr, tag->name, p));
      const std::size_t close = t.find(quote, p + 1);
      if (close == std::string_view::npos) return std::string_view::npos;
      tag->attrs[attr] = xml_unescape(t.substr(p + 1, close - p - 1));
      p = close + 1;
    }
  }

  void on_comment(std::string_view body) {
    std::size_t p = 0;
    while (p < body.size() && std::isspace(static_cast<unsigned char>(body[p]))) ++p;
    if (!body.substr(p).starts_with("cmcsurf")) return;
    std::size_t line_begin = body.find('\n', p);
    while (line_begin != std::string_view::npos) {
      ++line_begin;
      std::size_t line_end = body.find('\n', line_begin);
      std::string_view line =
          body.substr(line_begin, line_end == std::string_view::npos ? std::string_view::npos
                                                                     : line_end - line_begin);
      std::string key, value;
      if (parse_metadata_line(line, &key, &value)) metadata_[key] = value;
      line_begin = line_end;
    }
  }

  void on_tag(const Tag& tag) {
    if (tag.closing) {
      if (stack_.empty() || stack_.back() != tag.name)
        fail(fmt::format("malformed XML header: unexpected </{}>", tag.name));
      stack_.pop_back();
      root_closed_ = stack_.empty();
      return;
    }
    const std::string parent = stack_.empty() ? "" : stack_.back();
    if (stack_.empty() && tag.name != "VTKFile")
      fail(fmt::format("the root element is <{}>; expected <VTKFile type=\"{}\">", tag.name,
                       root_type_));
    on_element(tag, parent);
    if (!tag.self_closing) stack_.push_back(tag.name);
  }

  const char* kind_;
  const char* root_type_;
  std::string source_;
  std::vector<std::string> stack_;
  std::map<std::string, std::string> metadata_;
  bool in_appended_ = false;
  bool root_closed_ = false;
  std::size_t data_start_ = 0;

 protected:
  bool root_closed() const { return root_closed_; }
};

// A .vti header: one ImageData piece of Float32/Float64 PointData arrays in raw appended
// data. `cubic`: the extent must be "0 N-1 0 N-1 0 N-1" (a whole file); otherwise any extent
// (a piece of a .pvti).
class HeaderParser final : public XmlHeaderScanner {
 public:
  explicit HeaderParser(std::string source, bool cubic = true)
      : XmlHeaderScanner("VTI", "ImageData", std::move(source)), cubic_(cubic) {}

  int n() const { return int(extent_[1] + 1); }  // points per axis of a cubic extent
  const Extent& extent() const { return extent_; }
  int header_bytes() const { return header_bytes_; }
  const std::vector<ArrayInfo>& arrays() const { return arrays_; }
  const std::vector<std::uint64_t>& field_data_offsets() const { return field_data_offsets_; }

 protected:
  void reset() override {
    arrays_.clear();
    field_data_offsets_.clear();
    have_extent_ = false;
    extent_ = {};
    header_bytes_ = 0;
    pieces_ = 0;
  }

  const char* missing_end() const override {
    return "no <AppendedData encoding=\"raw\"> section found";
  }

  void on_element(const Tag& tag, const std::string& parent) override {
    if (tag.name == "VTKFile") header_bytes_ = check_vtkfile(tag);
    else if (tag.name == "ImageData") on_imagedata(tag);
    else if (tag.name == "Piece") on_piece(tag);
    else if (tag.name == "DataArray") on_dataarray(tag, parent);
    else if (tag.name == "AppendedData") on_appended(tag);
  }

 private:
  void on_imagedata(const Tag& tag) {
    const std::string* we = attr(tag, "WholeExtent");
    if (!we) fail("<ImageData> has no WholeExtent attribute");
    const auto e = parse_extent(*we);
    if (!e) fail(fmt::format("malformed WholeExtent=\"{}\"; expected six integers", *we));
    const auto& x = *e;
    if (cubic_) {
      if (x[0] != 0 || x[2] != 0 || x[4] != 0 || x[1] != x[3] || x[3] != x[5] || x[1] < 0 ||
          x[1] >= (1 << 20))
        fail(fmt::format("WholeExtent=\"{}\" is not supported; only a cubic extent "
                         "\"0 N-1 0 N-1 0 N-1\" with the same N >= 1 in all directions", *we));
    } else {
      for (int a = 0; a < 3; ++a)
        if (x[2 * a] < 0 || x[2 * a + 1] < x[2 * a] || x[2 * a + 1] >= (1 << 20))
          fail(fmt::format("WholeExtent=\"{}\" is not supported; expected 0 <= lo <= hi < 2^20 "
                           "along every axis", *we));
    }
    extent_ = x;
    have_extent_ = true;
  }

  void on_piece(const Tag& tag) {
    if (!have_extent_) fail("<Piece> appears before <ImageData WholeExtent=...>");
    if (++pieces_ > 1) fail("more than one <Piece> is not supported; only a single piece");
    if (const std::string* ext = attr(tag, "Extent")) {
      const auto e = parse_extent(*ext);
      if (!e || *e != extent_)
        fail(fmt::format("Piece Extent=\"{}\" differs from WholeExtent=\"{}\"; only a single piece "
                         "covering the whole extent is supported", *ext, extent_text(extent_)));
    }
  }

  void on_dataarray(const Tag& tag, const std::string& parent) {
    if (parent == "FieldData") {  // metadata copies; the comment is authoritative
      // Appended ones still take bytes of <AppendedData>: the tail check steps over them.
      const std::string* format = attr(tag, "format");
      const std::string* off = attr(tag, "offset");
      std::uint64_t offset = 0;
      if (format && *format == "appended") {
        if (!off ||
            std::from_chars(off->data(), off->data() + off->size(), offset).ec != std::errc())
          fail("an appended FieldData DataArray has no valid offset attribute");
        field_data_offsets_.push_back(offset);
      }
      return;
    }
    const std::string* name_attr = attr(tag, "Name");
    const std::string name = name_attr ? *name_attr : "(unnamed)";
    if (parent == "CellData")
      fail(fmt::format("CellData array '{}' is not supported; only PointData arrays (cmcsurf "
                       "writes cell-centred values as points at the cell centres)", name));
    if (parent != "PointData")
      fail(fmt::format("DataArray '{}' inside <{}> is not supported; only <PointData> arrays", name,
                       parent));
    if (!name_attr || name_attr->empty()) fail("a PointData DataArray has no Name");
    const std::string* type = attr(tag, "type");
    if (!type || (*type != "Float32" && *type != "Float64"))
      fail(fmt::format("DataArray '{}' has type=\"{}\"; only Float32 or Float64 are supported",
                       name, type ? *type : "(missing)"));
    if (const std::string* nc = attr(tag, "NumberOfComponents"); nc && *nc != "1")
      fail(fmt::format("DataArray '{}' has NumberOfComponents=\"{}\"; only scalar arrays (1) are "
                       "supported", name, *nc));
    const std::string* format = attr(tag, "format");
    if (!format || *format != "appended")
      fail(fmt::format("DataArray '{}' has format=\"{}\"; only format=\"appended\" with "
                       "<AppendedData encoding=\"raw\"> is supported", name,
                       format ? *format : "(missing)"));
    const std::string* off = attr(tag, "offset");
    std::uint64_t offset = 0;
    if (!off ||
        std::from_chars(off->data(), off->data() + off->size(), offset).ec != std::errc())
      fail(fmt::format("DataArray '{}' has no valid offset attribute", name));
    for (const auto& a : arrays_)
      if (a.name == name) fail(fmt::format("two PointData arrays are named '{}'", name));
    arrays_.push_back({name, *type == "Float32", offset});
  }

  void on_appended(const Tag& tag) {
    const std::string* enc = attr(tag, "encoding");
    if (!enc || *enc != "raw")
      fail(fmt::format("AppendedData encoding=\"{}\" is not supported; only encoding=\"raw\"",
                       enc ? *enc : "(missing)"));
    if (!have_extent_) fail("<AppendedData> appears before <ImageData WholeExtent=...>");
    if (tag.self_closing) fail("<AppendedData/> is empty");
    start_appended();
  }

  bool cubic_;
  std::vector<ArrayInfo> arrays_;
  std::vector<std::uint64_t> field_data_offsets_;
  Extent extent_{};
  bool have_extent_ = false;
  int header_bytes_ = 0;
  int pieces_ = 0;
};

// A .pvti: PImageData with a cubic WholeExtent, PPointData of scalar Float32/Float64 arrays and
// the pieces' extents and files; nothing is appended.
class PvtiParser final : public XmlHeaderScanner {
 public:
  explicit PvtiParser(std::string source)
      : XmlHeaderScanner("PVTI", "PImageData", std::move(source)) {}

  PvtiHeader header;

 protected:
  void reset() override {
    header = PvtiHeader{};
    have_extent_ = false;
  }
  bool complete() const override { return root_closed(); }
  const char* missing_end() const override { return "the file ends before </VTKFile>"; }

  void on_element(const Tag& tag, const std::string& parent) override {
    if (tag.name == "VTKFile") {
      check_vtkfile(tag);
    } else if (tag.name == "PImageData") {
      const std::string* we = attr(tag, "WholeExtent");
      if (!we) fail("<PImageData> has no WholeExtent attribute");
      const auto e = parse_extent(*we);
      if (!e) fail(fmt::format("malformed WholeExtent=\"{}\"; expected six integers", *we));
      const auto& x = *e;
      if (x[0] != 0 || x[2] != 0 || x[4] != 0 || x[1] != x[3] || x[3] != x[5] || x[1] < 1 ||
          x[1] >= (1 << 20))
        fail(fmt::format("WholeExtent=\"{}\" is not supported; only a cubic extent "
                         "\"0 N 0 N 0 N\" with the same N >= 1 in all directions", *we));
      if (const std::string* g = attr(tag, "GhostLevel"); g && *g != "0")
        fail(fmt::format("GhostLevel=\"{}\" is not supported; only pieces without ghost "
                         "levels (0)", *g));
      header.whole_extent = x;
      have_extent_ = true;
    } else if (tag.name == "PDataArray") {
      const std::string* name_attr = attr(tag, "Name");
      const std::string name = name_attr ? *name_attr : "(unnamed)";
      if (parent == "PCellData")
        fail(fmt::format("PCellData array '{}' is not supported; only PPointData arrays (cmcsurf "
                         "writes cell-centred values as points at the cell centres)", name));
      if (parent != "PPointData")
        fail(fmt::format("PDataArray '{}' inside <{}> is not supported; only <PPointData> arrays",
                         name, parent));
      if (!name_attr || name_attr->empty()) fail("a PPointData PDataArray has no Name");
      const std::string* type = attr(tag, "type");
      if (!type || (*type != "Float32" && *type != "Float64"))
        fail(fmt::format("PDataArray '{}' has type=\"{}\"; only Float32 or Float64 are supported",
                         name, type ? *type : "(missing)"));
      if (const std::string* nc = attr(tag, "NumberOfComponents"); nc && *nc != "1")
        fail(fmt::format("PDataArray '{}' has NumberOfComponents=\"{}\"; only scalar arrays (1) "
                         "are supported", name, *nc));
      for (const auto& a : header.arrays)
        if (a.first == name) fail(fmt::format("two PPointData arrays are named '{}'", name));
      header.arrays.emplace_back(name, *type == "Float32");
    } else if (tag.name == "Piece") {
      if (!have_extent_ || parent != "PImageData")
        fail("<Piece> outside <PImageData WholeExtent=...>");
      if (header.pieces.size() >= kMaxPvtiPieces)
        fail(fmt::format("more than {} pieces", kMaxPvtiPieces));
      const std::string* ext = attr(tag, "Extent");
      const std::string* source = attr(tag, "Source");
      if (!ext) fail(fmt::format("piece {} has no Extent", header.pieces.size()));
      const auto e = parse_extent(*ext);
      if (!e) fail(fmt::format("piece {} has a malformed Extent=\"{}\"; expected six integers",
                               header.pieces.size(), *ext));
      if (!source || source->empty())
        fail(fmt::format("piece {} (Extent=\"{}\") has no Source file", header.pieces.size(),
                         *ext));
      header.pieces.push_back({*e, *source});
    }
  }

 private:
  bool have_extent_ = false;
};

// Reads an array's m[0] x m[1] x m[2] point values (x fastest): of the first cells[a] points
// per axis, point i is cell first[a] + i, checked finite and put into f where f's block holds
// it; the other points (the periodic wrap, or the next piece's first points) are skipped.
// False on a read error.
template <class T>
bool read_values(std::istream& in, Field& f, const std::array<int, 3>& m,
                 const std::array<int, 3>& cells, const std::array<long long, 3>& first,
                 std::vector<char>& bytes,
                 const std::function<void(double, const std::array<long long, 3>&)>& non_finite) {
  const std::size_t row_bytes = std::size_t(m[0]) * sizeof(T);
  bytes.resize(row_bytes * std::size_t(m[1]));
  const auto& o = f.offset();
  // The x range of the rows that lands in f's block.
  const long long i0 = std::max<long long>(0, o[0] - first[0]);
  const long long i1 = std::min<long long>(cells[0], o[0] + f.nx() - first[0]);
  for (int k = 0; k < m[2]; ++k) {
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!in) return false;
    if (k >= cells[2]) continue;
    const long long lz = first[2] + k - o[2];
    for (int j = 0; j < cells[1]; ++j) {
      const char* src = bytes.data() + std::size_t(j) * row_bytes;
      for (int i = 0; i < cells[0]; ++i) {
        T v;
        std::memcpy(&v, src + std::size_t(i) * sizeof(T), sizeof(T));
        if (!std::isfinite(v)) non_finite(double(v), {first[0] + i, first[1] + j, first[2] + k});
      }
      const long long ly = first[1] + j - o[1];
      if (lz < 0 || lz >= f.nz() || ly < 0 || ly >= f.ny() || i1 <= i0) continue;
      double* row = &f(int(first[0] + i0 - o[0]), int(ly), int(lz));
      if constexpr (std::is_same_v<T, double>) {
        std::memcpy(row, src + std::size_t(i0) * sizeof(T), sizeof(double) * std::size_t(i1 - i0));
      } else {
        for (long long i = i0; i < i1; ++i) {
          T v;
          std::memcpy(&v, src + std::size_t(i) * sizeof(T), sizeof(T));
          row[i - i0] = static_cast<double>(v);
        }
      }
    }
  }
  return true;
}

// A read-only, seekable stream buffer over bytes in memory (parse_vti).
class MemoryBuffer : public std::streambuf {
 public:
  explicit MemoryBuffer(std::span<const unsigned char> bytes) {
    // The get area is never written through: no put area, and putback only re-reads.
    char* first = const_cast<char*>(reinterpret_cast<const char*>(bytes.data()));
    setg(first, first, first + bytes.size());
  }

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    const off_type base = dir == std::ios_base::beg   ? 0
                          : dir == std::ios_base::cur ? gptr() - eback()
                                                      : egptr() - eback();
    return seekpos(pos_type(base + off), std::ios_base::in);
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode) override {
    const off_type p = off_type(pos);
    if (p < 0 || p > egptr() - eback()) return pos_type(off_type(-1));
    setg(eback(), eback() + p, egptr());
    return pos;
  }
};

VtiData read_vti_stream(std::istream& in, std::uint64_t file_size, HeaderParser& parser,
                        const VtiReadOptions& options);

}  // namespace

void write_vti(const std::filesystem::path& path, const std::vector<VtiArray>& arrays, bool float32,
               const std::map<std::string, std::string>& metadata) {
  if (arrays.empty()) throw std::invalid_argument("write_vti: no arrays for " + path.string());
  std::set<std::string> names;
  for (const VtiArray& a : arrays) {
    if (!a.field) throw std::invalid_argument("write_vti: null field '" + a.name + "'");
    if (a.field->n() != arrays[0].field->n())
      throw std::invalid_argument(fmt::format("write_vti: array '{}' has N={}, '{}' has N={}",
                                              a.name, a.field->n(), arrays[0].name,
                                              arrays[0].field->n()));
    if (a.field->offset() != arrays[0].field->offset() ||
        a.field->size() != arrays[0].field->size())
      throw std::invalid_argument(fmt::format("write_vti: arrays '{}' and '{}' are on other blocks",
                                              a.name, arrays[0].name));
    if (!a.field->whole() && a.field->ghost() < 1)
      throw std::invalid_argument(fmt::format(
          "write_vti: block '{}' has no ghost layer for the next block's first points", a.name));
    if (a.name.empty() || !names.insert(a.name).second)
      throw std::invalid_argument("write_vti: array names must be unique and non-empty: '" +
                                  a.name + "'");
  }
  const Field& first = *arrays[0].field;
  const int n = first.n();
  const std::size_t elem = float32 ? sizeof(float) : sizeof(double);
  const std::uint64_t points =
      std::uint64_t(first.nx() + 1) * (first.ny() + 1) * (first.nz() + 1);
  const std::uint64_t bytes = points * elem;
  const char* type = float32 ? "Float32" : "Float64";
  const std::string extent = point_extent(first);

  std::string head = comment_head(metadata);
  head += "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\">\n";
  head += fmt::format("  <ImageData WholeExtent=\"{}\" {}>\n", extent, origin_spacing(n));
  std::string field_data;
  for (const auto& [key, value] : metadata) {
    if (const auto v = parse_finite_number(value))
      field_data += fmt::format(
          "      <DataArray type=\"Float64\" Name=\"{}\" NumberOfTuples=\"1\" format=\"ascii\">"
          "{:.17g}</DataArray>\n",
          xml_escape(key), *v);
  }
  if (!field_data.empty()) head += "    <FieldData>\n" + field_data + "    </FieldData>\n";
  head += fmt::format("    <Piece Extent=\"{}\">\n", extent);
  head += fmt::format("      <PointData Scalars=\"{}\">\n", xml_escape(arrays[0].name));
  std::uint64_t offset = 0;
  for (const VtiArray& a : arrays) {
    head += fmt::format(
        "        <DataArray type=\"{}\" Name=\"{}\" format=\"appended\" offset=\"{}\"/>\n", type,
        xml_escape(a.name), offset);
    offset += sizeof(std::uint64_t) + bytes;
  }
  head += "      </PointData>\n      <CellData>\n      </CellData>\n    </Piece>\n"
          "  </ImageData>\n  <AppendedData encoding=\"raw\">\n   _";

  AtomicWriter writer(path);
  std::ostream& os = writer.stream();
  os.write(head.data(), static_cast<std::streamsize>(head.size()));
  std::vector<float> slab32;
  std::vector<double> slab64;
  for (const VtiArray& a : arrays) {
    os.write(reinterpret_cast<const char*>(&bytes), sizeof(bytes));
    if (float32) write_values(os, *a.field, slab32);
    else write_values(os, *a.field, slab64);
  }
  const std::string_view tail = "\n  </AppendedData>\n</VTKFile>\n";
  os.write(tail.data(), static_cast<std::streamsize>(tail.size()));
  writer.commit();
}

std::string format_pvti(int n, const std::vector<std::string>& names, bool float32,
                        const std::map<std::string, std::string>& metadata,
                        const std::vector<PvtiPiece>& pieces) {
  if (names.empty()) throw std::invalid_argument("format_pvti: no arrays");
  const char* type = float32 ? "Float32" : "Float64";
  std::string text = comment_head(metadata);
  text += "<VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\">\n";
  text += fmt::format("  <PImageData WholeExtent=\"0 {0} 0 {0} 0 {0}\" GhostLevel=\"0\" {1}>\n", n,
                      origin_spacing(n));
  text += fmt::format("    <PPointData Scalars=\"{}\">\n", xml_escape(names[0]));
  for (const std::string& name : names)
    text += fmt::format("      <PDataArray type=\"{}\" Name=\"{}\"/>\n", type, xml_escape(name));
  text += "    </PPointData>\n    <PCellData>\n    </PCellData>\n";
  for (const PvtiPiece& p : pieces)
    text += fmt::format("    <Piece Extent=\"{} {} {} {} {} {}\" Source=\"{}\"/>\n", p.extent[0],
                        p.extent[1], p.extent[2], p.extent[3], p.extent[4], p.extent[5],
                        xml_escape(p.source));
  text += "  </PImageData>\n</VTKFile>\n";
  return text;
}

VtiData read_vti(const std::filesystem::path& path, int ghost) {
  VtiReadOptions options;
  options.ghost = ghost;
  return read_vti(path, options);
}

VtiData read_vti(const std::filesystem::path& path, const VtiReadOptions& options) {
  require_regular_file(path, "VTI file");
  HeaderParser parser(path.string());
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  if (ec) parser.fail(ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) parser.fail(std::strerror(errno));
  return read_vti_stream(in, file_size, parser, options);
}

VtiData parse_vti(std::span<const unsigned char> bytes, const VtiReadOptions& options,
                  const std::string& source) {
  HeaderParser parser(source);
  MemoryBuffer buffer(bytes);
  std::istream in(&buffer);
  return read_vti_stream(in, bytes.size(), parser, options);
}

namespace {

// The header of the VTI file in `in` (positioned at the start): a growing prefix is read until
// it parses up to the '_' marker, at most kMaxVtiHeaderBytes.
void read_header(std::istream& in, HeaderParser& parser) {
  std::string text;
  std::size_t chunk = 1 << 16;
  while (true) {
    const std::size_t old = text.size();
    chunk = std::min(chunk, kMaxVtiHeaderBytes - old);
    text.resize(old + chunk);
    in.read(text.data() + old, static_cast<std::streamsize>(chunk));
    text.resize(old + static_cast<std::size_t>(in.gcount()));
    const bool at_eof = !in;
    if (parser.parse(text, at_eof)) break;
    if (text.size() >= kMaxVtiHeaderBytes)
      parser.fail(fmt::format("no '_' marker of <AppendedData encoding=\"raw\"> in the first {} "
                              "bytes; cmcsurf reads raw appended VTI files with a header below "
                              "that size",
                              kMaxVtiHeaderBytes));
    chunk = text.size();
  }
  if (parser.arrays().empty()) parser.fail("no PointData arrays found");
}

// "4^3 = 64" or "4 x 5 x 6 = 120" points.
std::string points_text(const std::array<int, 3>& m) {
  const std::uint64_t count = std::uint64_t(m[0]) * m[1] * m[2];
  if (m[0] == m[1] && m[1] == m[2]) return fmt::format("{}^3 = {}", m[0], count);
  return fmt::format("{} x {} x {} = {}", m[0], m[1], m[2], count);
}

std::pair<std::uint64_t, std::uint64_t> byte_range(const HeaderParser& parser, const ArrayInfo& a,
                                                   const std::array<int, 3>& m) {
  const std::uint64_t expected = std::uint64_t(m[0]) * m[1] * m[2] * (a.float32 ? 4 : 8);
  const std::uint64_t begin = parser.data_start() + a.offset;
  return {begin, begin + parser.header_bytes() + expected};
}

// Every array's bytes (its byte count, then m[0] m[1] m[2] values) lie in the file, and no two
// arrays share bytes. Returns the last one's end and name.
std::pair<std::uint64_t, std::string> check_byte_ranges(const HeaderParser& parser,
                                                        const std::array<int, 3>& m,
                                                        std::uint64_t file_size) {
  const int hb = parser.header_bytes();
  struct Range {
    std::uint64_t begin, end;
    std::string name;
  };
  std::vector<Range> ranges;
  for (const ArrayInfo& a : parser.arrays()) {
    // First the offset alone: data_start + offset must not wrap past 2^64 to the header.
    if (a.offset > file_size)
      parser.fail(fmt::format("array '{}' has offset {} beyond the end of the file ({} bytes)",
                              a.name, a.offset, file_size));
    const auto [begin, end] = byte_range(parser, a, m);
    if (begin + hb > file_size || end > file_size)
      parser.fail(
          fmt::format("file truncated: array '{}' needs bytes {}..{} but the file has {} bytes",
                      a.name, begin, end, file_size));
    ranges.push_back({begin, end, a.name});
  }
  std::sort(ranges.begin(), ranges.end(),
            [](const Range& x, const Range& y) { return x.begin < y.begin; });
  for (std::size_t q = 1; q < ranges.size(); ++q)
    if (ranges[q].begin < ranges[q - 1].end)
      parser.fail(fmt::format("arrays '{}' and '{}' overlap in the appended data",
                              ranges[q - 1].name, ranges[q].name));
  const auto last = std::max_element(
      ranges.begin(), ranges.end(), [](const Range& x, const Range& y) { return x.end < y.end; });
  return {last->end, last->name};
}

// A layout key, if any, is cmcsurf's periodic one: another value is not "no wrap".
void check_layout(const HeaderParser& parser, const std::map<std::string, std::string>& metadata) {
  const auto layout = metadata.find(kVtiLayoutKey);
  if (layout != metadata.end() && layout->second != kVtiPeriodicLayout)
    parser.fail(fmt::format("{}={} in the '<!-- cmcsurf' comment is not a layout cmcsurf knows; "
                            "accepted: {}={} (N + 1 points per axis, the last the wrap) or no {} "
                            "line (N points per axis)",
                            kVtiLayoutKey, layout->second, kVtiLayoutKey, kVtiPeriodicLayout,
                            kVtiLayoutKey));
}

// After the arrays' bytes (data_end, and any appended FieldData) the file holds only the
// closing tags: data short of its byte counts would otherwise read the tags as values.
void check_tail(std::istream& in, const HeaderParser& parser,
                std::pair<std::uint64_t, std::string> last, std::uint64_t file_size) {
  auto& [data_end, name] = last;
  const int hb = parser.header_bytes();
  for (const std::uint64_t offset : parser.field_data_offsets()) {
    const std::uint64_t begin = parser.data_start() + offset;
    if (offset > file_size || begin + hb > file_size)
      parser.fail(fmt::format("a FieldData array has offset {} beyond the end of the file ({} "
                              "bytes)", offset, file_size));
    std::uint64_t count = 0;
    in.clear();
    in.seekg(static_cast<std::streamoff>(begin));
    in.read(reinterpret_cast<char*>(&count), hb);
    if (!in || count > file_size - begin - hb)
      parser.fail(fmt::format("a FieldData array at offset {} has a byte count of {} beyond the "
                              "end of the file ({} bytes)", offset, count, file_size));
    if (begin + hb + count > data_end) {
      data_end = begin + hb + count;
      name = "(FieldData)";
    }
  }
  constexpr std::uint64_t kMaxTail = 4096;
  const std::uint64_t size = file_size - data_end;
  std::string tail(std::size_t(std::min(size, kMaxTail)), '\0');
  in.clear();
  in.seekg(static_cast<std::streamoff>(data_end));
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  if (!in) parser.fail(fmt::format("read error after the appended data: {}", std::strerror(errno)));
  std::size_t p = 0;
  auto skip_space = [&] {
    while (p < tail.size() && std::isspace(static_cast<unsigned char>(tail[p]))) ++p;
  };
  auto take = [&](std::string_view word) {
    skip_space();
    if (tail.compare(p, word.size(), word) != 0) return false;
    p += word.size();
    return true;
  };
  const bool closed = size <= kMaxTail && take("</AppendedData>") && take("</VTKFile>");
  skip_space();
  if (!closed || p != tail.size())
    parser.fail(fmt::format(
        "the appended data should end with array '{}' at byte {} (the arrays' byte counts), "
        "followed by </AppendedData> and </VTKFile> alone, but {} bytes follow there starting "
        "\"{}\" (the data is shorter or longer than its byte counts say)",
        name, data_end, size, comment_escape(tail.substr(0, 24), false)));
}

// Reads array a (m points per axis; cells and first as read_values takes them) into f.
void read_array(std::istream& in, const HeaderParser& parser, const ArrayInfo& a, Field& f,
                const std::array<int, 3>& m, const std::array<int, 3>& cells,
                const std::array<long long, 3>& first, std::vector<char>& bytes) {
  const auto [begin, end] = byte_range(parser, a, m);
  const int hb = parser.header_bytes();
  const std::uint64_t expected = end - begin - hb;
  in.clear();
  in.seekg(static_cast<std::streamoff>(begin));
  std::uint64_t count = 0;
  in.read(reinterpret_cast<char*>(&count), hb);  // little-endian: low bytes first
  if (count != expected)
    parser.fail(fmt::format("array '{}' has a byte count of {} but {} {} values need {} bytes",
                            a.name, count, points_text(m), a.float32 ? "Float32" : "Float64",
                            expected));
  auto non_finite = [&](double v, const std::array<long long, 3>& c) {
    parser.fail(fmt::format("array '{}' holds a non-finite value ({}) at cell ({}, {}, {})",
                            a.name, v, c[0], c[1], c[2]));
  };
  const bool ok = a.float32 ? read_values<float>(in, f, m, cells, first, bytes, non_finite)
                            : read_values<double>(in, f, m, cells, first, bytes, non_finite);
  if (!ok) parser.fail(fmt::format("read error in array '{}': {}", a.name, std::strerror(errno)));
}

// `in` holds file_size bytes, positioned at the start.
VtiData read_vti_stream(std::istream& in, std::uint64_t file_size, HeaderParser& parser,
                        const VtiReadOptions& options) {
  read_header(in, parser);
  // m points per axis; with cmcsurf's periodic layout they are the N cells plus the wrap.
  const int m = parser.n();
  check_layout(parser, parser.metadata());
  const bool wrapped = parser.metadata().contains(kVtiLayoutKey);
  if (wrapped && m < 2) parser.fail("a periodic layout needs at least 2 points per axis");
  const int n = wrapped ? m - 1 : m;
  if (n > options.max_n)
    parser.fail(fmt::format("N = {} exceeds the limit {} of this command", n, options.max_n));
  if (options.ghost < 0 || options.ghost > n)
    throw std::invalid_argument(fmt::format("read_vti: ghost width {} for N={}", options.ghost, n));

  std::vector<ArrayInfo> wanted;
  if (!options.only.empty()) {
    std::string names;
    for (const ArrayInfo& a : parser.arrays()) {
      if (a.name == options.only) wanted.push_back(a);
      names += (names.empty() ? "'" : ", '") + a.name + "'";
    }
    if (wanted.empty())
      parser.fail(fmt::format("no array '{}' (found {})", options.only, names));
  } else {
    wanted = parser.arrays();
  }
  check_tail(in, parser, check_byte_ranges(parser, {m, m, m}, file_size), file_size);

  VtiData result;
  result.n = n;
  result.metadata = std::move(parser.metadata());
  std::vector<char> bytes;
  for (const ArrayInfo& a : wanted) {
    Field f(n, options.ghost);
    read_array(in, parser, a, f, {m, m, m}, {n, n, n}, {0, 0, 0}, bytes);
    f.exchange_halo();
    result.arrays.emplace(a.name, std::move(f));
  }
  return result;
}

}  // namespace

PvtiHeader parse_pvti(std::string_view text, const std::string& source) {
  PvtiParser parser(source);
  if (text.size() > kMaxPvtiBytes)
    parser.fail(fmt::format("{} bytes; a .pvti of cmcsurf is below {} bytes", text.size(),
                            kMaxPvtiBytes));
  parser.parse(text, true);
  if (parser.header.arrays.empty()) parser.fail("no PPointData arrays found");
  if (parser.header.pieces.empty()) parser.fail("no <Piece> found");
  parser.header.metadata = std::move(parser.metadata());
  return std::move(parser.header);
}

void read_vti_piece(const std::filesystem::path& path, const std::array<long long, 6>& extent,
                    const std::vector<VtiPieceTarget>& targets, const std::string& pvti) {
  require_regular_file(path, fmt::format("piece of {}", pvti));
  HeaderParser parser(path.string(), false);
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  if (ec) parser.fail(fmt::format("{} (a piece of {})", ec.message(), pvti));
  std::ifstream in(path, std::ios::binary);
  if (!in) parser.fail(fmt::format("{} (a piece of {})", std::strerror(errno), pvti));
  read_header(in, parser);
  check_layout(parser, parser.metadata());
  if (parser.extent() != extent)
    parser.fail(fmt::format("its extent \"{}\" differs from the Extent=\"{}\" that {} gives it",
                            extent_text(parser.extent()), extent_text(extent), pvti));
  std::array<int, 3> m{}, cells{};
  std::array<long long, 3> first{};
  for (int a = 0; a < 3; ++a) {
    m[a] = int(extent[2 * a + 1] - extent[2 * a] + 1);
    cells[a] = m[a] - 1;  // the last points are the next piece's first ones, or the wrap
    first[a] = extent[2 * a];
  }
  check_tail(in, parser, check_byte_ranges(parser, m, file_size), file_size);
  std::vector<char> bytes;
  for (const VtiPieceTarget& t : targets) {
    const auto it = std::find_if(parser.arrays().begin(), parser.arrays().end(),
                                 [&](const ArrayInfo& a) { return a.name == t.name; });
    if (it == parser.arrays().end())
      parser.fail(fmt::format("no array '{}', which {} lists", t.name, pvti));
    if (it->float32 != t.float32)
      parser.fail(fmt::format("array '{}' is {}, but {} says {}", t.name,
                              it->float32 ? "Float32" : "Float64", pvti,
                              t.float32 ? "Float32" : "Float64"));
    read_array(in, parser, *it, *t.field, m, cells, first, bytes);
  }
}

}  // namespace cmcsurf
