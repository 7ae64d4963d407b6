#include "mesh/writers.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <Model/COM/NMR_DLLInterfaces.h>

#include "common/atomic_file.h"

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

namespace {

// lib3mf 1.8's C API: every call returns 0 or an error code; the message is the instance's.
void check_3mf(LIB3MFRESULT rc, NMR::PLib3MFBase* instance, const char* what,
               const std::filesystem::path& path) {
  if (rc == 0) return;
  DWORD code = 0;
  LPCSTR message = nullptr;
  if (instance != nullptr) NMR::lib3mf_getlasterror(instance, &code, &message);
  throw std::runtime_error(fmt::format("3MF '{}': lib3mf {} failed (0x{:x}{}{})", path.string(),
                                       what, rc, message ? ": " : "", message ? message : ""));
}

// Releases a lib3mf instance at the end of a scope.
struct Lib3mfHandle {
  NMR::PLib3MFBase* p = nullptr;
  Lib3mfHandle() = default;
  Lib3mfHandle(const Lib3mfHandle&) = delete;
  Lib3mfHandle& operator=(const Lib3mfHandle&) = delete;
  ~Lib3mfHandle() {
    if (p != nullptr) NMR::lib3mf_release(p);
  }
};

// The writer's stream callbacks (lib3mf 1.8 calls them with C linkage semantics: 0 = done).
// They never report an error: an exception thrown inside lib3mf on a failed callback ends the
// process, so a failed stream is left failed and AtomicWriter::commit reports it by name.
unsigned write_callback(unsigned char* data, unsigned bytes, void* user) {
  static_cast<std::ostream*>(user)->write(reinterpret_cast<const char*>(data), bytes);
  return 0;
}
unsigned seek_callback(unsigned long long position, void* user) {
  static_cast<std::ostream*>(user)->seekp(std::streamoff(position));
  return 0;
}

constexpr NMR::eModelUnit kLib3mfUnits[] = {NMR::MODELUNIT_MICROMETER, NMR::MODELUNIT_MILLIMETER,
                                            NMR::MODELUNIT_CENTIMETER, NMR::MODELUNIT_METER,
                                            NMR::MODELUNIT_INCH};

}  // namespace

void write_3mf(const std::filesystem::path& path, const TriMesh& m, const std::string& unit,
               const MeshMetadata& meta) {
  check_not_periodic(m, "3MF");
  if (m.vertices.size() >= 0xffffffffu || m.triangles.size() >= 0xffffffffu)
    throw std::runtime_error(
        fmt::format("3MF '{}': more than 2^32 vertices or triangles", path.string()));
  NMR::eModelUnit model_unit = NMR::MODELUNIT_MILLIMETER;
  bool known = false;
  for (std::size_t u = 0; u < std::size(kUnits); ++u)
    if (unit == kUnits[u].unit) model_unit = kLib3mfUnits[u], known = true;
  if (!known) throw std::invalid_argument(fmt::format("3MF: unknown unit '{}'", unit));
  Lib3mfHandle model, object, item, writer;
  check_3mf(NMR::lib3mf_createmodel(&model.p), nullptr, "createmodel", path);
  check_3mf(NMR::lib3mf_model_setunit(model.p, model_unit), model.p, "setunit", path);
  for (const auto& [key, value] : {std::pair{"Title", &meta.title},
                                   std::pair{"Description", &meta.description},
                                   std::pair{"Application", &meta.application}})
    if (!value->empty())
      check_3mf(NMR::lib3mf_model_addmetadatautf8(model.p, key, value->c_str()), model.p,
                "addmetadata", path);
  check_3mf(NMR::lib3mf_model_addmeshobject(model.p, &object.p), model.p, "addmeshobject", path);
  {
    std::vector<NMR::MODELMESHVERTEX> vertices(m.vertices.size());
    for (std::size_t v = 0; v < m.vertices.size(); ++v)
      for (int c = 0; c < 3; ++c) vertices[v].m_fPosition[c] = float(m.vertices[v][c]);
    std::vector<NMR::MODELMESHTRIANGLE> triangles(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c) triangles[t].m_nIndices[c] = m.triangles[t][c];
    check_3mf(NMR::lib3mf_meshobject_setgeometry(object.p, vertices.data(),
                                                 DWORD(vertices.size()), triangles.data(),
                                                 DWORD(triangles.size())),
              object.p, "setgeometry", path);
  }
  if (!meta.title.empty())
    check_3mf(NMR::lib3mf_object_setnameutf8(object.p, meta.title.c_str()), object.p, "setname",
              path);
  check_3mf(NMR::lib3mf_model_addbuilditem(model.p, object.p, nullptr, &item.p), model.p,
            "addbuilditem", path);
  check_3mf(NMR::lib3mf_model_querywriter(model.p, "3mf", &writer.p), model.p, "querywriter", path);
  AtomicWriter out(path);
  check_3mf(NMR::lib3mf_writer_writetocallback(writer.p, reinterpret_cast<void*>(&write_callback),
                                               reinterpret_cast<void*>(&seek_callback),
                                               &out.stream()),
            writer.p, "write", path);
  out.commit();
}

Read3mf read_3mf(const std::filesystem::path& path) {
  Read3mf r;
  Lib3mfHandle model, reader, resources, items;
  check_3mf(NMR::lib3mf_createmodel(&model.p), nullptr, "createmodel", path);
  check_3mf(NMR::lib3mf_model_queryreader(model.p, "3mf", &reader.p), model.p, "queryreader", path);
  check_3mf(NMR::lib3mf_reader_readfromfileutf8(reader.p, path.c_str()), reader.p, "read", path);
  DWORD unit = 0;
  check_3mf(NMR::lib3mf_model_getunit(model.p, &unit), model.p, "getunit", path);
  for (std::size_t u = 0; u < std::size(kUnits); ++u)
    if (DWORD(kLib3mfUnits[u]) == unit) r.unit = kUnits[u].unit;
  DWORD count = 0;
  check_3mf(NMR::lib3mf_model_getmetadatacount(model.p, &count), model.p, "getmetadatacount", path);
  for (DWORD i = 0; i < count; ++i) {
    std::string kv[2];
    for (int which = 0; which < 2; ++which) {
      ULONG needed = 0;
      auto get = which == 0 ? NMR::lib3mf_model_getmetadatakeyutf8
                            : NMR::lib3mf_model_getmetadatavalueutf8;
      check_3mf(get(model.p, i, nullptr, 0, &needed), model.p, "getmetadata", path);
      std::vector<char> buffer(needed + 1, '\0');
      check_3mf(get(model.p, i, buffer.data(), ULONG(buffer.size()), &needed), model.p,
                "getmetadata", path);
      kv[which] = buffer.data();
    }
    r.metadata.emplace_back(kv[0], kv[1]);
  }
  check_3mf(NMR::lib3mf_model_getmeshobjects(model.p, &resources.p), model.p, "getmeshobjects",
            path);
  for (BOOL more = true;;) {
    check_3mf(NMR::lib3mf_resourceiterator_movenext(resources.p, &more), resources.p, "movenext",
              path);
    if (!more) break;
    Lib3mfHandle object;
    check_3mf(NMR::lib3mf_resourceiterator_getcurrent(resources.p, &object.p), resources.p,
              "getcurrent", path);
    if (r.objects++ > 0) continue;
    DWORD nv = 0, nt = 0;
    check_3mf(NMR::lib3mf_meshobject_getvertexcount(object.p, &nv), object.p, "getvertexcount",
              path);
    check_3mf(NMR::lib3mf_meshobject_gettrianglecount(object.p, &nt), object.p, "gettrianglecount",
              path);
    std::vector<NMR::MODELMESHVERTEX> vertices(nv);
    std::vector<NMR::MODELMESHTRIANGLE> triangles(nt);
    check_3mf(NMR::lib3mf_meshobject_getvertices(object.p, vertices.data(), nv, nullptr), object.p,
              "getvertices", path);
    check_3mf(NMR::lib3mf_meshobject_gettriangleindices(object.p, triangles.data(), nt, nullptr),
              object.p, "gettriangleindices", path);
    r.vertices = nv;
    r.triangles = nt;
    for (const auto& v : vertices)
      r.mesh.vertices.push_back({v.m_fPosition[0], v.m_fPosition[1], v.m_fPosition[2]});
    for (const auto& t : triangles)
      r.mesh.triangles.push_back({t.m_nIndices[0], t.m_nIndices[1], t.m_nIndices[2]});
  }
  check_3mf(NMR::lib3mf_model_getbuilditems(model.p, &items.p), model.p, "getbuilditems", path);
  for (BOOL more = true;;) {
    check_3mf(NMR::lib3mf_builditemiterator_movenext(items.p, &more), items.p, "movenext", path);
    if (!more) break;
    ++r.build_items;
  }
  return r;
}

void write_mesh(const std::filesystem::path& path, MeshFormat format, const TriMesh& mesh,
                const std::string& unit, const MeshMetadata& meta) {
  switch (format) {
    case MeshFormat::kStl: return write_stl(path, mesh);
    case MeshFormat::kPly: return write_ply(path, mesh);
    case MeshFormat::kObj: return write_obj(path, mesh);
    case MeshFormat::k3mf: return write_3mf(path, mesh, unit, meta);
  }
}

}  // namespace cmcsurf
