#include "io/tet_mesh_writers.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "common/wall_clock.h"
#include "common/atomic_file.h"

#ifdef CMCSURF_HAVE_HDF5
#include <hdf5.h>
#endif

namespace cmcsurf {

namespace {

std::string period_label(const std::array<long, 3>& k) {
  auto one = [](char axis, long v) {
    return fmt::format("{}{}{}", axis, v < 0 ? "M" : "", std::labs(v));
  };
  return one('X', k[0]) + "_" + one('Y', k[1]) + "_" + one('Z', k[2]);
}

// Coordinates are written with 17 digits (they round-trip exactly), so pairs read back coincide
// modulo the period as they do here.
void write_msh(const TetMesh& m, std::ostream& os, const std::string& title) {
  const auto classes = pair_classes(m);
  // Entities: volume 1 holds the tets and the nodes no pair names; surface 1 the masters;
  // surface 2 + c the slaves of translation class c. A node sits on one entity only.
  std::vector<int> entity(m.nodes.size(), 0);  // 0: the volume; s > 0: surface s
  for (std::size_t c = 0; c < classes.size(); ++c)
    for (const PeriodicPair* p : classes[c].pairs) entity[p->slave] = int(c) + 2;
  for (const auto& p : m.pairs) entity[p.master] = 1;
  const int surfaces = int(classes.size()) + 1;
  std::vector<std::vector<std::size_t>> by_entity(std::size_t(surfaces) + 1);
  for (std::size_t i = 0; i < m.nodes.size(); ++i) by_entity[std::size_t(entity[i])].push_back(i);
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const auto& x : m.nodes)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], x[a]), hi[a] = std::max(hi[a], x[a]);
  // Node tags in file order (entity by entity), as readers that index points by position
  // (meshio) assume.
  std::vector<std::size_t> tag(m.nodes.size());
  std::size_t next = 1;
  for (const auto& b : by_entity)
    for (std::size_t i : b) tag[i] = next++;
  const std::string box = fmt::format("{} {} {} {} {} {}", lo[0], lo[1], lo[2], hi[0], hi[1],
                                      hi[2]);
  std::string s;
  auto out = std::back_inserter(s);
  fmt::format_to(out, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  fmt::format_to(out, "$Comments\n{}\n$EndComments\n", title);
  fmt::format_to(out, "$PhysicalNames\n1\n3 1 \"solid\"\n$EndPhysicalNames\n");
  fmt::format_to(out, "$Entities\n0 0 {} 1\n", surfaces);
  for (int t = 1; t <= surfaces; ++t) fmt::format_to(out, "{} {} 0 0\n", t, box);
  fmt::format_to(out, "1 {} 1 1 0\n$EndEntities\n", box);
  std::size_t blocks = 0;
  for (const auto& b : by_entity) blocks += !b.empty();
  fmt::format_to(out, "$Nodes\n{} {} 1 {}\n", blocks, m.nodes.size(), m.nodes.size());
  for (std::size_t e = 0; e < by_entity.size(); ++e) {
    const auto& b = by_entity[e];
    if (b.empty()) continue;
    fmt::format_to(out, "{} {} 0 {}\n", e == 0 ? 3 : 2, e == 0 ? 1 : e, b.size());
    for (std::size_t i : b) fmt::format_to(out, "{}\n", tag[i]);
    for (std::size_t i : b)
      fmt::format_to(out, "{:.17g} {:.17g} {:.17g}\n", m.nodes[i][0], m.nodes[i][1],
                     m.nodes[i][2]);
  }
  fmt::format_to(out, "$EndNodes\n$Elements\n1 {} 1 {}\n3 1 4 {}\n", m.tets.size(),
                 m.tets.size(), m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    fmt::format_to(out, "{} {} {} {} {}\n", t + 1, tag[m.tets[t][0]], tag[m.tets[t][1]],
                   tag[m.tets[t][2]], tag[m.tets[t][3]]);
  fmt::format_to(out, "$EndElements\n");
  // Each link maps the master surface onto a slave one by a translation (row-major 4x4).
  fmt::format_to(out, "$Periodic\n{}\n", classes.size());
  for (std::size_t c = 0; c < classes.size(); ++c) {
    const Vec3 t = classes[c].pairs.front()->translation;
    fmt::format_to(out, "2 {} 1\n16 1 0 0 {:.17g} 0 1 0 {:.17g} 0 0 1 {:.17g} 0 0 0 1\n{}\n",
                   c + 2, t[0], t[1], t[2], classes[c].pairs.size());
    for (const PeriodicPair* p : classes[c].pairs)
      fmt::format_to(out, "{} {}\n", tag[p->slave], tag[p->master]);
  }
  fmt::format_to(out, "$EndPeriodic\n");
  os << s;
}

void write_inp(const TetMesh& m, std::ostream& os, const std::string& title) {
  std::string s;
  auto out = std::back_inserter(s);
  fmt::format_to(out, "*HEADING\n{}\n", title);
  fmt::format_to(out,
                 "** Periodic pairs: for each translation, node sets S_<label> and M_<label>\n"
                 "** list slave i and master i in the same order (UNSORTED), x_S = x_M + "
                 "translation,\n** ready for *EQUATION with node sets (docs/volume_mesh.md).\n");
  fmt::format_to(out, "*NODE, NSET=ALL_NODES\n");
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    fmt::format_to(out, "{}, {:.17g}, {:.17g}, {:.17g}\n", i + 1, m.nodes[i][0], m.nodes[i][1],
                   m.nodes[i][2]);
  fmt::format_to(out, "*ELEMENT, TYPE=C3D4, ELSET=SOLID\n");
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    fmt::format_to(out, "{}, {}, {}, {}, {}\n", t + 1, m.tets[t][0] + 1, m.tets[t][1] + 1,
                   m.tets[t][2] + 1, m.tets[t][3] + 1);
  auto node_set = [&](const std::string& name, const PairClass& c, bool slaves) {
    fmt::format_to(out, "*NSET, NSET={}, UNSORTED\n", name);
    for (std::size_t i = 0; i < c.pairs.size(); ++i)
      fmt::format_to(out, "{}{}", (slaves ? c.pairs[i]->slave : c.pairs[i]->master) + 1,
                     i + 1 == c.pairs.size() || i % 16 == 15 ? "\n" : ", ");
  };
  for (const PairClass& c : pair_classes(m)) {
    const Vec3 t = c.pairs.front()->translation;
    const std::string label = period_label(c.periods);
    fmt::format_to(out, "** translation {} = ({:.17g}, {:.17g}, {:.17g}): {} pairs\n", label,
                   t[0], t[1], t[2], c.pairs.size());
    node_set("S_" + label, c, true);
    node_set("M_" + label, c, false);
  }
  os << s;
}

std::vector<std::int64_t> master_of(const TetMesh& m) {
  std::vector<std::int64_t> master(m.nodes.size(), -1);
  for (const auto& p : m.pairs) master[p.slave] = p.master;
  return master;
}

void write_vtu(const TetMesh& m, std::ostream& os, const std::string& title) {
  std::string s;
  auto out = std::back_inserter(s);
  fmt::format_to(out, "<?xml version=\"1.0\"?>\n<!-- {} -->\n", title);
  fmt::format_to(out, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                      "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
                      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                 m.nodes.size(), m.tets.size());
  fmt::format_to(out, "<PointData>\n<DataArray type=\"Int64\" Name=\"periodic_master\" "
                      "format=\"ascii\">\n");
  for (auto v : master_of(m)) fmt::format_to(out, "{}\n", v);
  fmt::format_to(out, "</DataArray>\n</PointData>\n<Points>\n<DataArray type=\"Float64\" "
                      "NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (const auto& x : m.nodes) fmt::format_to(out, "{:.17g} {:.17g} {:.17g}\n", x[0], x[1], x[2]);
  fmt::format_to(out, "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" "
                      "Name=\"connectivity\" format=\"ascii\">\n");
  for (const auto& t : m.tets) fmt::format_to(out, "{} {} {} {}\n", t[0], t[1], t[2], t[3]);
  fmt::format_to(out, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" "
                      "format=\"ascii\">\n");
  for (std::size_t t = 0; t < m.tets.size(); ++t) fmt::format_to(out, "{}\n", 4 * (t + 1));
  fmt::format_to(out, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" "
                      "format=\"ascii\">\n");
  for (std::size_t t = 0; t < m.tets.size(); ++t) fmt::format_to(out, "10\n");  // VTK_TETRA
  fmt::format_to(out, "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
  os << s;
}

// The heavy data's datasets, as XDMF names them (h5: the HDF5 file; empty: inline XML).
constexpr const char* kTopology = "/topology";
constexpr const char* kGeometry = "/geometry";
constexpr const char* kPeriodicMaster = "/periodic_master";

void write_xdmf(const TetMesh& m, std::ostream& os, const std::string& title,
                const std::string& h5) {
  std::string s;
  auto out = std::back_inserter(s);
  const char* format = h5.empty() ? "XML" : "HDF";
  // A DataItem's body: the values inline, or where they are in the HDF5 file.
  auto body = [&](const char* dataset, const auto& write_inline) {
    if (h5.empty())
      write_inline();
    else
      fmt::format_to(out, "{}:{}\n", h5, dataset);
  };
  fmt::format_to(out, "<?xml version=\"1.0\"?>\n<!-- {} -->\n", title);
  fmt::format_to(out, "<Xdmf Version=\"3.0\">\n<Domain>\n<Grid Name=\"solid\" "
                      "GridType=\"Uniform\">\n");
  fmt::format_to(out, "<Topology TopologyType=\"Tetrahedron\" NumberOfElements=\"{}\">\n"
                      "<DataItem Dimensions=\"{} 4\" NumberType=\"Int\" Precision=\"8\" "
                      "Format=\"{}\">\n",
                 m.tets.size(), m.tets.size(), format);
  body(kTopology, [&] {
    for (const auto& t : m.tets) fmt::format_to(out, "{} {} {} {}\n", t[0], t[1], t[2], t[3]);
  });
  fmt::format_to(out, "</DataItem>\n</Topology>\n<Geometry GeometryType=\"XYZ\">\n"
                      "<DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
                      "Format=\"{}\">\n",
                 m.nodes.size(), format);
  body(kGeometry, [&] {
    for (const auto& x : m.nodes)
      fmt::format_to(out, "{:.17g} {:.17g} {:.17g}\n", x[0], x[1], x[2]);
  });
  fmt::format_to(out, "</DataItem>\n</Geometry>\n<Attribute Name=\"periodic_master\" "
                      "AttributeType=\"Scalar\" Center=\"Node\">\n<DataItem Dimensions=\"{}\" "
                      "NumberType=\"Int\" Precision=\"8\" Format=\"{}\">\n",
                 m.nodes.size(), format);
  body(kPeriodicMaster, [&] {
    for (auto v : master_of(m)) fmt::format_to(out, "{}\n", v);
  });
  fmt::format_to(out, "</DataItem>\n</Attribute>\n</Grid>\n</Domain>\n</Xdmf>\n");
  os << s;
}

#ifdef CMCSURF_HAVE_HDF5
// The XDMF file's heavy data: nodes (float64 N x 3), tets (int64 T x 4, 0-based) and
// periodic_master (int64 N).
void write_xdmf_h5(const TetMesh& m, const std::filesystem::path& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are thrown, not printed
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) throw std::runtime_error(fmt::format("cannot create '{}'", path.string()));
  bool ok = true;
  auto put = [&](const char* name, hid_t type, std::vector<hsize_t> dims, const void* data) {
    const hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
    const hid_t set = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ok = ok && set >= 0 && H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
    if (set >= 0) H5Dclose(set);
    H5Sclose(space);
  };
  const std::vector<std::int64_t> master = master_of(m);
  put(kTopology, H5T_NATIVE_INT64, {m.tets.size(), 4}, m.tets.data());
  put(kGeometry, H5T_NATIVE_DOUBLE, {m.nodes.size(), 3}, m.nodes.data());
  put(kPeriodicMaster, H5T_NATIVE_INT64, {m.nodes.size()}, master.data());
  ok = H5Fclose(file) >= 0 && ok;
  if (!ok) throw std::runtime_error(fmt::format("cannot write '{}' (HDF5)", path.string()));
}
#endif

}  // namespace

std::vector<PairClass> pair_classes(const TetMesh& m) {
  std::map<std::array<long, 3>, PairClass> by;
  for (const auto& p : m.pairs) {
    std::array<long, 3> k;
    for (int a = 0; a < 3; ++a) k[a] = std::lround(p.translation[a] / m.period[a]);
    PairClass& c = by[k];
    c.periods = k;
    c.pairs.push_back(&p);
  }
  std::vector<PairClass> v;
  for (auto& [k, c] : by) v.push_back(std::move(c));
  return v;
}

const char* tet_mesh_format_list() { return "msh|inp|vtu|xdmf"; }

const char* tet_mesh_format_name(TetMeshFormat f) {
  switch (f) {
    case TetMeshFormat::kMsh: return "msh";
    case TetMeshFormat::kInp: return "inp";
    case TetMeshFormat::kVtu: return "vtu";
    case TetMeshFormat::kXdmf: return "xdmf";
  }
  return "";
}

TetMeshFormat tet_mesh_format(const std::string& format, const std::filesystem::path& out) {
  std::string f = format;
  if (f.empty()) {
    f = out.extension().string();
    if (!f.empty()) f = f.substr(1);
    std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return std::tolower(c); });
  }
  for (auto k : {TetMeshFormat::kMsh, TetMeshFormat::kInp, TetMeshFormat::kVtu,
                 TetMeshFormat::kXdmf})
    if (f == tet_mesh_format_name(k)) return k;
  throw std::invalid_argument(
      fmt::format("got '{}'; accepted: {}", f, tet_mesh_format_list()));
}

bool xdmf_hdf5_available() {
#ifdef CMCSURF_HAVE_HDF5
  return true;
#else
  return false;
#endif
}

std::filesystem::path xdmf_heavy_data_path(const std::filesystem::path& xdmf) {
  std::filesystem::path h5 = xdmf;
  return h5.replace_extension(".h5");
}

void write_tet_mesh_with_report(const TetMesh& m, TetMeshFormat f,
                                const std::filesystem::path& path, const std::string& title,
                                nlohmann::json report) {
  namespace fs = std::filesystem;
  const auto t0 = WallClock::now();
  if (path.has_parent_path()) ensure_directory(path.parent_path());
  // XDMF's heavy data, written by the HDF5 library under a temporary name of its own.
  const bool h5 = f == TetMeshFormat::kXdmf && xdmf_hdf5_available();
  const fs::path h5_path = xdmf_heavy_data_path(path);
  const fs::path h5_temp = h5 ? temporary_name(h5_path) : fs::path();
  struct RemoveOnExit {
    fs::path path;
    ~RemoveOnExit() {
      std::error_code ec;
      if (!path.empty()) fs::remove(path, ec);
    }
  } cleanup{h5_temp};
#ifdef CMCSURF_HAVE_HDF5
  if (h5) write_xdmf_h5(m, h5_temp);
#endif
  AtomicWriter w(path);
  switch (f) {
    case TetMeshFormat::kMsh: write_msh(m, w.stream(), title); break;
    case TetMeshFormat::kInp: write_inp(m, w.stream(), title); break;
    case TetMeshFormat::kVtu: write_vtu(m, w.stream(), title); break;
    case TetMeshFormat::kXdmf:
      write_xdmf(m, w.stream(), title, h5 ? h5_path.filename().string() : std::string());
      break;
  }
  w.finish_writing();
  report["file"] = path.filename().string();
  report["file_bytes"] = fs::file_size(w.temp_path());
  report["format"] = tet_mesh_format_name(f);
  if (f == TetMeshFormat::kXdmf) {
    report["xdmf_data"] = h5 ? "HDF5" : "inline XML (no HDF5 file: built without libhdf5-dev)";
    if (h5) {
      report["heavy_data_file"] = h5_path.filename().string();
      report["heavy_data_bytes"] = fs::file_size(h5_temp);
    }
  }
  report["write_seconds"] = seconds_since(t0);
  report["version"] = CMCSURF_VERSION;
  // FILE.json marks FILE complete: all are whole under temporary names before any is renamed,
  // the heavy data and FILE first.
  AtomicWriter json(path.string() + ".json");
  json.stream() << report.dump(2) << '\n';
  json.finish_writing();
  if (h5) {
    std::error_code ec;
    fs::rename(h5_temp, h5_path, ec);
    if (ec)
      throw std::runtime_error(fmt::format("cannot rename '{}' to '{}': {}", h5_temp.string(),
                                           h5_path.string(), ec.message()));
  }
  w.commit();
  json.commit();
}

}  // namespace cmcsurf
