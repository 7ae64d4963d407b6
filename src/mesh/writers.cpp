#include "mesh/writers.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "io/atomic_file.h"

namespace cmcsurf {

namespace {

struct UnitName {
  const char* unit;
  const char* name_3mf;
};
constexpr UnitName kUnits[] = {{"um", "micron"}, {"mm", "millimeter"}, {"cm", "centimeter"},
                               {"m", "meter"},   {"in", "inch"}};

template <class T>
void put(std::string& s, T v) {  // little-endian hosts only (x86-64, aarch64)
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

Vec3 unit_normal(const TriMesh& m, const std::array<std::uint32_t, 3>& t) {
  const Vec3 u = mesh_edge(m, t[0], t[1]), w = mesh_edge(m, t[0], t[2]);
  Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (l > 0)
    for (double& c : n) c /= l;
  return n;
}

// Streams the buffer out in chunks of about 1 MiB.
void flush_chunk(AtomicWriter& w, std::string& buf, bool force) {
  if (force || buf.size() > (1u << 20)) {
    w.stream().write(buf.data(), std::streamsize(buf.size()));
    buf.clear();
  }
}

void check_not_periodic(const TriMesh& m, const char* what) {
  if (m.period[0] > 0 || m.period[1] > 0 || m.period[2] > 0)
    throw std::invalid_argument(fmt::format("{}: a periodic (torus) mesh has no embedding", what));
}

}  // namespace

MeshFormat parse_mesh_format(const std::string& name) {
  if (name == "stl") return MeshFormat::kStl;
  if (name == "ply") return MeshFormat::kPly;
  if (name == "obj") return MeshFormat::kObj;
  if (name == "3mf") return MeshFormat::k3mf;
  throw std::invalid_argument(fmt::format("got '{}'; accepted: {}", name, mesh_format_list()));
}
const char* mesh_format_extension(MeshFormat f) {
  switch (f) {
    case MeshFormat::kStl: return "stl";
    case MeshFormat::kPly: return "ply";
    case MeshFormat::kObj: return "obj";
    case MeshFormat::k3mf: return "3mf";
  }
  return "";
}
const char* mesh_format_list() { return "stl|ply|obj|3mf"; }

bool is_mesh_unit(const std::string& unit) {
  for (const auto& u : kUnits)
    if (unit == u.unit) return true;
  return false;
}
const char* mesh_units_list() { return "um|mm|cm|m|in"; }
std::string unit_3mf_name(const std::string& unit) {
  for (const auto& u : kUnits)
    if (unit == u.unit) return u.name_3mf;
  throw std::invalid_argument(fmt::format("unit '{}'; accepted: {}", unit, mesh_units_list()));
}

void write_stl(const std::filesystem::path& path, const TriMesh& m) {
  check_not_periodic(m, "STL");
  if (m.triangles.size() > 0xffffffffu) throw std::runtime_error("STL: more than 2^32 triangles");
  AtomicWriter w(path);
  std::string s;
  std::string header = "cmcsurf binary STL";
  header.resize(80, ' ');  // must not start with "solid"
  s += header;
  put(s, std::uint32_t(m.triangles.size()));
  for (const auto& t : m.triangles) {
    const Vec3 n = unit_normal(m, t);
    for (double c : n) put(s, float(c));
    for (int k = 0; k < 3; ++k)
      for (double c : m.vertices[t[k]]) put(s, float(c));
    put(s, std::uint16_t(0));
    flush_chunk(w, s, false);
  }
  flush_chunk(w, s, true);
  w.commit();
}

void write_ply(const std::filesystem::path& path, const TriMesh& m) {
  check_not_periodic(m, "PLY");
  AtomicWriter w(path);
  std::string s = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment cmcsurf\nelement vertex {}\n"
      "property float x\nproperty float y\nproperty float z\nelement face {}\n"
      "property list uchar uint vertex_indices\nend_header\n",
      m.vertices.size(), m.triangles.size());
  for (const Vec3& v : m.vertices) {
    for (double c : v) put(s, float(c));
    flush_chunk(w, s, false);
  }
  for (const auto& t : m.triangles) {
    put(s, std::uint8_t(3));
    for (std::uint32_t i : t) put(s, i);
    flush_chunk(w, s, false);
  }
  flush_chunk(w, s, true);
  w.commit();
}

void write_obj(const std::filesystem::path& path, const TriMesh& m) {
  check_not_periodic(m, "OBJ");
  AtomicWriter w(path);
  std::string buf;
  auto flush = [&](bool force) { flush_chunk(w, buf, force); };
  buf += "# cmcsurf OBJ: counter-clockwise faces seen from outside\n";
  for (const Vec3& v : m.vertices) {
    fmt::format_to(std::back_inserter(buf), "v {:.9g} {:.9g} {:.9g}\n", v[0], v[1], v[2]);
    flush(false);
  }
  for (const auto& t : m.triangles) {
    fmt::format_to(std::back_inserter(buf), "f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    flush(false);
  }
  flush(true);
  w.commit();
}

std::uint32_t crc32(std::string_view data, std::uint32_t crc) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (unsigned char b : data) crc = table[(crc ^ b) & 0xff] ^ (crc >> 8);
  return ~crc;
}

std::string make_stored_zip(const std::vector<ZipEntry>& entries) {
  std::string out, central;
  for (const ZipEntry& e : entries) {
    if (e.data.size() >= 0xffffffffu || out.size() >= 0xffffffffu)
      throw std::runtime_error("zip: an entry or the archive exceeds 4 GiB (no zip64)");
    const std::uint32_t crc = crc32(e.data), size = std::uint32_t(e.data.size());
    const std::uint32_t offset = std::uint32_t(out.size());
    // Local file header: version 2.0, no flags, method 0 (stored), DOS time 1980-01-01.
    put(out, std::uint32_t(0x04034b50));
    put(out, std::uint16_t(20));
    put(out, std::uint16_t(0));
    put(out, std::uint16_t(0));
    put(out, std::uint16_t(0));
    put(out, std::uint16_t(0x21));
    put(out, crc);
    put(out, size);
    put(out, size);
    put(out, std::uint16_t(e.name.size()));
    put(out, std::uint16_t(0));
    out += e.name;
    out += e.data;
    // Central directory record.
    put(central, std::uint32_t(0x02014b50));
    put(central, std::uint16_t(20));
    put(central, std::uint16_t(20));
    put(central, std::uint16_t(0));
    put(central, std::uint16_t(0));
    put(central, std::uint16_t(0));
    put(central, std::uint16_t(0x21));
    put(central, crc);
    put(central, size);
    put(central, size);
    put(central, std::uint16_t(e.name.size()));
    put(central, std::uint16_t(0));  // extra
    put(central, std::uint16_t(0));  // comment
    put(central, std::uint16_t(0));  // disk
    put(central, std::uint16_t(0));  // internal attributes
    put(central, std::uint32_t(0));  // external attributes
    put(central, offset);
    central += e.name;
  }
  const std::uint32_t cd_offset = std::uint32_t(out.size());
  out += central;
  put(out, std::uint32_t(0x06054b50));
  put(out, std::uint16_t(0));
  put(out, std::uint16_t(0));
  put(out, std::uint16_t(entries.size()));
  put(out, std::uint16_t(entries.size()));
  put(out, std::uint32_t(central.size()));
  put(out, cd_offset);
  put(out, std::uint16_t(0));
  return out;
}

void write_3mf(const std::filesystem::path& path, const TriMesh& m, const std::string& unit) {
  check_not_periodic(m, "3MF");
  const std::string content_types =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
      "<Default Extension=\"rels\" "
      "ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
      "<Default Extension=\"model\" "
      "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>\n";
  const std::string rels =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
      "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
      "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";
  std::string model = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<model unit=\"{}\" xml:lang=\"en-US\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n"
      "<metadata name=\"Application\">cmcsurf</metadata>\n"
      "<resources>\n<object id=\"1\" type=\"model\">\n<mesh>\n<vertices>\n",
      unit_3mf_name(unit));
  model.reserve(model.size() + 60 * m.vertices.size() + 45 * m.triangles.size());
  auto out = std::back_inserter(model);
  for (const Vec3& v : m.vertices)
    fmt::format_to(out, "<vertex x=\"{:.9g}\" y=\"{:.9g}\" z=\"{:.9g}\"/>\n", v[0], v[1], v[2]);
  model += "</vertices>\n<triangles>\n";
  for (const auto& t : m.triangles)
    fmt::format_to(out, "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n", t[0], t[1], t[2]);
  model += "</triangles>\n</mesh>\n</object>\n</resources>\n<build><item objectid=\"1\"/></build>\n"
           "</model>\n";
  write_file_atomic(path, make_stored_zip({{"[Content_Types].xml", content_types},
                                           {"_rels/.rels", rels},
                                           {"3D/3dmodel.model", std::move(model)}}));
}

void write_mesh(const std::filesystem::path& path, MeshFormat format, const TriMesh& mesh,
                const std::string& unit) {
  switch (format) {
    case MeshFormat::kStl: return write_stl(path, mesh);
    case MeshFormat::kPly: return write_ply(path, mesh);
    case MeshFormat::kObj: return write_obj(path, mesh);
    case MeshFormat::k3mf: return write_3mf(path, mesh, unit);
  }
}

}  // namespace cmcsurf
