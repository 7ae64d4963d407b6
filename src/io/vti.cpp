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

#include "io/atomic_file.h"

namespace cmcsurf {

static_assert(std::endian::native == std::endian::little,
              "VTI I/O copies raw little-endian bytes; a big-endian host needs byte swapping");

namespace {

// ---- shared helpers ---------------------------------------------------------

std::string xml_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string xml_unescape(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '&') {
      out += s[i];
      continue;
    }
    const std::size_t semi = s.find(';', i);
    const std::string_view ent = semi == std::string_view::npos ? "" : s.substr(i + 1, semi - i - 1);
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

std::string extent_string(int n) { return fmt::format("0 {0} 0 {0} 0 {0}", n - 1); }

// ---- writer -----------------------------------------------------------------

// The N^3 cell values plus the periodic wrap: (N+1)^3 points, point i on each axis holding
// cell i mod N, so that VTK's point grid covers the whole unit cell.
template <class T>
void write_values(std::ostream& os, const Field& f, std::vector<T>& slab) {
  const int n = f.n(), m = n + 1;
  slab.resize(std::size_t(m) * m);
  for (int k = 0; k < m; ++k) {
    for (int j = 0; j < m; ++j) {
      const double* row = f.data() + f.index(0, j % n, k % n);
      T* dst = slab.data() + std::size_t(j) * m;
      for (int i = 0; i < n; ++i) dst[i] = static_cast<T>(row[i]);
      dst[n] = static_cast<T>(row[0]);
    }
    os.write(reinterpret_cast<const char*>(slab.data()),
             static_cast<std::streamsize>(slab.size() * sizeof(T)));
  }
}

// ---- reader: a small scanner for the header of our own format ---------------

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

class HeaderParser {
 public:
  explicit HeaderParser(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& msg) const {
    throw std::runtime_error(fmt::format("cannot read VTI file '{}': {}", source_, msg));
  }

  // Parses text from the start; true once the '_' marker after
  // <AppendedData> is found, false if more text is needed. Throws on
  // unsupported content; at_eof turns "need more" into an error.
  bool parse(std::string_view text, bool at_eof) {
    reset();
    std::size_t pos = 0;
    while (true) {
      if (in_appended_) {
        while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
        if (pos >= text.size()) return need_more(at_eof, "the file ends before the '_' marker of <AppendedData>");
        if (text[pos] != '_')
          fail(fmt::format("expected the '_' marker at the start of <AppendedData>, found '{}'", text[pos]));
        data_start_ = pos + 1;
        return true;
      }
      const std::size_t lt = text.find('<', pos);
      if (lt == std::string_view::npos)
        return need_more(at_eof, "no <AppendedData encoding=\"raw\"> section found");
      const std::string_view rest = text.substr(lt);
      if (rest.starts_with("<!--")) {
        const std::size_t end = text.find("-->", lt + 4);
        if (end == std::string_view::npos) return need_more(at_eof, "the file ends inside an XML comment");
        on_comment(text.substr(lt + 4, end - lt - 4));
        pos = end + 3;
        continue;
      }
      if (rest.starts_with("<?") || rest.starts_with("<!")) {
        const std::size_t end = text.find('>', lt);
        if (end == std::string_view::npos) return need_more(at_eof, "the file ends inside the XML header");
        pos = end + 1;
        continue;
      }
      Tag tag;
      const std::size_t end = scan_tag(text, lt, &tag);
      if (end == std::string_view::npos) return need_more(at_eof, "the file ends inside the XML header");
      pos = end;
      on_tag(tag);
    }
  }

  int n() const { return n_; }
  int header_bytes() const { return header_bytes_; }
  std::size_t data_start() const { return data_start_; }
  const std::vector<ArrayInfo>& arrays() const { return arrays_; }
  std::map<std::string, std::string>& metadata() { return metadata_; }

 private:
  void reset() {
    stack_.clear();
    arrays_.clear();
    metadata_.clear();
    n_ = -1;
    header_bytes_ = 0;
    pieces_ = 0;
    in_appended_ = false;
    data_start_ = 0;
  }

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
        fail(fmt::format("unquoted value of attribute {} in <{}> near byte {}", attr, tag->name, p));
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
      std::string_view line = body.substr(
          line_begin, line_end == std::string_view::npos ? std::string_view::npos : line_end - line_begin);
      std::string key, value;
      if (parse_metadata_line(line, &key, &value)) metadata_[key] = value;
      line_begin = line_end;
    }
  }

  static const std::string* attr(const Tag& tag, const char* name) {
    const auto it = tag.attrs.find(name);
    return it == tag.attrs.end() ? nullptr : &it->second;
  }

  // Six integers "x0 x1 y0 y1 z0 z1".
  std::optional<std::array<long long, 6>> parse_extent(const std::string& s) const {
    std::array<long long, 6> e{};
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

  void on_tag(const Tag& tag) {
    if (tag.closing) {
      if (stack_.empty() || stack_.back() != tag.name)
        fail(fmt::format("malformed XML header: unexpected </{}>", tag.name));
      stack_.pop_back();
      return;
    }
    const std::string parent = stack_.empty() ? "" : stack_.back();
    if (stack_.empty() && tag.name != "VTKFile")
      fail(fmt::format("the root element is <{}>; expected <VTKFile type=\"ImageData\">", tag.name));
    if (tag.name == "VTKFile") on_vtkfile(tag);
    else if (tag.name == "ImageData") on_imagedata(tag);
    else if (tag.name == "Piece") on_piece(tag);
    else if (tag.name == "DataArray") on_dataarray(tag, parent);
    else if (tag.name == "AppendedData") on_appended(tag);
    if (!tag.self_closing) stack_.push_back(tag.name);
  }

  void on_vtkfile(const Tag& tag) {
    const std::string* type = attr(tag, "type");
    if (!type || *type != "ImageData")
      fail(fmt::format("VTKFile type=\"{}\" is not supported; only type=\"ImageData\"",
                       type ? *type : "(missing)"));
    if (const std::string* c = attr(tag, "compressor"); c && !c->empty())
      fail(fmt::format("compressed data (compressor=\"{}\") is not supported; only uncompressed "
                       "raw appended data (as written by cmcsurf)", *c));
    const std::string* order = attr(tag, "byte_order");
    if (!order || *order != "LittleEndian")
      fail(fmt::format("byte_order=\"{}\" is not supported; only byte_order=\"LittleEndian\"",
                       order ? *order : "(missing)"));
    const std::string* ht = attr(tag, "header_type");
    if (!ht || *ht == "UInt32") header_bytes_ = 4;  // VTK's default when absent
    else if (*ht == "UInt64") header_bytes_ = 8;
    else fail(fmt::format("header_type=\"{}\" is not supported; only UInt32 or UInt64", *ht));
  }

  void on_imagedata(const Tag& tag) {
    const std::string* we = attr(tag, "WholeExtent");
    if (!we) fail("<ImageData> has no WholeExtent attribute");
    const auto e = parse_extent(*we);
    if (!e) fail(fmt::format("malformed WholeExtent=\"{}\"; expected six integers", *we));
    const auto& x = *e;
    if (x[0] != 0 || x[2] != 0 || x[4] != 0 || x[1] != x[3] || x[3] != x[5] || x[1] < 0 ||
        x[1] >= (1 << 20))
      fail(fmt::format("WholeExtent=\"{}\" is not supported; only a cubic extent "
                       "\"0 N-1 0 N-1 0 N-1\" with the same N >= 1 in all directions", *we));
    n_ = static_cast<int>(x[1] + 1);
  }

  void on_piece(const Tag& tag) {
    if (n_ < 0) fail("<Piece> appears before <ImageData WholeExtent=...>");
    if (++pieces_ > 1) fail("more than one <Piece> is not supported; only a single piece");
    if (const std::string* ext = attr(tag, "Extent")) {
      const auto e = parse_extent(*ext);
      if (!e || *e != parse_extent(extent_string(n_)).value())
        fail(fmt::format("Piece Extent=\"{}\" differs from WholeExtent=\"{}\"; only a single piece "
                         "covering the whole extent is supported", *ext, extent_string(n_)));
    }
  }

  void on_dataarray(const Tag& tag, const std::string& parent) {
    if (parent == "FieldData") return;  // metadata copies; the comment is authoritative
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
      fail(fmt::format("DataArray '{}' has type=\"{}\"; only Float32 or Float64 are supported", name,
                       type ? *type : "(missing)"));
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
    if (n_ < 0) fail("<AppendedData> appears before <ImageData WholeExtent=...>");
    if (tag.self_closing) fail("<AppendedData/> is empty");
    in_appended_ = true;
  }

  std::string source_;
  std::vector<std::string> stack_;
  std::vector<ArrayInfo> arrays_;
  std::map<std::string, std::string> metadata_;
  int n_ = -1;
  int header_bytes_ = 0;
  int pieces_ = 0;
  bool in_appended_ = false;
  std::size_t data_start_ = 0;
};

// Reads m^3 point values (x fastest) into the N^3 cells of f: m = N, or m = N + 1 with the
// periodic wrap, whose last point on each axis repeats the first and is skipped.
template <class T>
void read_values(std::istream& in, Field& f, int m, std::vector<char>& bytes) {
  const int n = f.n();
  bytes.resize(std::size_t(m) * m * sizeof(T));
  for (int k = 0; k < m; ++k) {
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (k >= n) continue;
    for (int j = 0; j < n; ++j) {
      double* row = &f(0, j, k);
      const char* src = bytes.data() + std::size_t(j) * m * sizeof(T);
      if constexpr (std::is_same_v<T, double>) {
        std::memcpy(row, src, sizeof(double) * n);
      } else {
        for (int i = 0; i < n; ++i) {
          T v;
          std::memcpy(&v, src + std::size_t(i) * sizeof(T), sizeof(T));
          row[i] = static_cast<double>(v);
        }
      }
    }
  }
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
    if (a.name.empty() || !names.insert(a.name).second)
      throw std::invalid_argument("write_vti: array names must be unique and non-empty: '" +
                                  a.name + "'");
  }
  const int n = arrays[0].field->n();
  const double h = 1.0 / n;
  const std::size_t elem = float32 ? sizeof(float) : sizeof(double);
  const std::uint64_t points = std::uint64_t(n + 1) * (n + 1) * (n + 1);
  const std::uint64_t bytes = points * elem;
  const char* type = float32 ? "Float32" : "Float64";
  const std::string extent = extent_string(n + 1);

  std::string head = "<?xml version=\"1.0\"?>\n<!-- cmcsurf\n";
  head += std::string(kVtiLayoutKey) + "=" + kVtiPeriodicLayout + "\n";
  for (const auto& [key, value] : metadata)
    if (key != kVtiLayoutKey)
      head += comment_escape(key, true) + "=" + comment_escape(value, false) + "\n";
  head += "-->\n";
  head += "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\">\n";
  head += fmt::format(
      "  <ImageData WholeExtent=\"{0}\" Origin=\"{1:.17g} {1:.17g} {1:.17g}\" "
      "Spacing=\"{2:.17g} {2:.17g} {2:.17g}\">\n",
      extent, h / 2, h);
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

VtiData read_vti(const std::filesystem::path& path, int ghost) {
  VtiReadOptions options;
  options.ghost = ghost;
  return read_vti(path, options);
}

VtiData read_vti(const std::filesystem::path& path, const VtiReadOptions& options) {
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

// `in` holds file_size bytes, positioned at the start.
VtiData read_vti_stream(std::istream& in, std::uint64_t file_size, HeaderParser& parser,
                        const VtiReadOptions& options) {
  // Read a growing prefix until the header parses up to the '_' marker, at most
  // kMaxVtiHeaderBytes.
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
  // m points per axis; with cmcsurf's periodic layout they are the N cells plus the wrap.
  const int m = parser.n();
  const auto layout = parser.metadata().find(kVtiLayoutKey);
  const bool wrapped = layout != parser.metadata().end() && layout->second == kVtiPeriodicLayout;
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
  const int hb = parser.header_bytes();
  auto byte_range = [&](const ArrayInfo& a) {
    const std::uint64_t expected = std::uint64_t(m) * m * m * (a.float32 ? 4 : 8);
    const std::uint64_t begin = parser.data_start() + a.offset;
    return std::pair{begin, begin + hb + expected};
  };
  // Every array's bytes lie in the file, and no two arrays share bytes.
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
    const auto [begin, end] = byte_range(a);
    if (begin + hb > file_size || end > file_size)
      parser.fail(fmt::format("file truncated: array '{}' needs bytes {}..{} but the file has {} bytes",
                              a.name, begin, end, file_size));
    ranges.push_back({begin, end, a.name});
  }
  std::sort(ranges.begin(), ranges.end(),
            [](const Range& x, const Range& y) { return x.begin < y.begin; });
  for (std::size_t q = 1; q < ranges.size(); ++q)
    if (ranges[q].begin < ranges[q - 1].end)
      parser.fail(fmt::format("arrays '{}' and '{}' overlap in the appended data",
                              ranges[q - 1].name, ranges[q].name));

  VtiData result;
  result.n = n;
  result.metadata = std::move(parser.metadata());
  std::vector<char> bytes;
  for (const ArrayInfo& a : wanted) {
    const auto [begin, end] = byte_range(a);
    const std::uint64_t expected = end - begin - hb;
    in.clear();
    in.seekg(static_cast<std::streamoff>(begin));
    std::uint64_t count = 0;
    in.read(reinterpret_cast<char*>(&count), hb);  // little-endian: low bytes first
    if (count != expected)
      parser.fail(fmt::format("array '{}' has a byte count of {} but {}^3 = {} {} values need {} bytes",
                              a.name, count, m, std::uint64_t(m) * m * m,
                              a.float32 ? "Float32" : "Float64", expected));
    Field f(n, options.ghost);
    if (a.float32) read_values<float>(in, f, m, bytes);
    else read_values<double>(in, f, m, bytes);
    if (!in) parser.fail(fmt::format("read error in array '{}': {}", a.name, std::strerror(errno)));
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          if (!std::isfinite(f(i, j, k)))
            parser.fail(fmt::format("array '{}' holds a non-finite value ({}) at cell ({}, {}, {})",
                                    a.name, f(i, j, k), i, j, k));
    f.exchange_halo();
    result.arrays.emplace(a.name, std::move(f));
  }
  return result;
}

}  // namespace

}  // namespace cmcsurf
