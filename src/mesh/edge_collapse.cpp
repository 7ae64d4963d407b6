#include "mesh/edge_collapse.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <numbers>
#include <queue>
#include <tuple>

namespace cmcsurf {

namespace {

// Symmetric 4x4 quadric: a x^2 + 2 b xy + ... of the plane n.x + d = 0, stored as its upper
// triangle (xx xy xz xd yy yz yd zz zd dd).
struct Quadric {
  std::array<double, 10> q{};
  double planes = 0.0;  // how many planes were summed
  static Quadric plane(const Vec3& n, double d) {
    return {{n[0] * n[0], n[0] * n[1], n[0] * n[2], n[0] * d, n[1] * n[1], n[1] * n[2],
             n[1] * d, n[2] * n[2], n[2] * d, d * d},
            1.0};
  }
  Quadric& operator+=(const Quadric& o) {
    for (int i = 0; i < 10; ++i) q[i] += o.q[i];
    planes += o.planes;
    return *this;
  }
  double operator()(const Vec3& p) const {
    const double x = p[0], y = p[1], z = p[2];
    return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
           2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
  }
  // The minimiser, when the 3x3 part is well conditioned.
  bool minimum(Vec3& out) const {
    const double a = q[0], b = q[1], c = q[2], d = q[4], e = q[5], f = q[7];
    const double det = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d);
    const double scale = a + d + f;
    if (!(std::abs(det) > 1e-6 * scale * scale * scale)) return false;
    const double rx = -q[3], ry = -q[6], rz = -q[8];
    // Cramer's rule on the symmetric system.
    out[0] = (rx * (d * f - e * e) - b * (ry * f - e * rz) + c * (ry * e - d * rz)) / det;
    out[1] = (a * (ry * f - e * rz) - rx * (b * f - c * e) + c * (b * rz - ry * c)) / det;
    out[2] = (a * (d * rz - ry * e) - b * (b * rz - ry * c) + rx * (b * e - c * d)) / det;
    return true;
  }
};

Vec3 normal_of(const Vec3& a, const Vec3& b, const Vec3& c) {
  return cross(sub(b, a), sub(c, a));
}

double length(const Vec3& v) { return std::sqrt(dot(v, v)); }

// The reference (collapse_edges_ref): the collapser as first written, frozen; the tests
// compare the optimised one below with it.

// Equal costs (flat stretches: most of a part's caps) go shortest edge first, then by the ends'
// positions, never by index: the order of these free collapses set the error (0.0069 to 0.013
// on a G network at a quarter of its triangles) and must not follow the input's order.
struct CandidateRef {
  float cost;
  float length2;  // the edge's squared length
  std::array<float, 3> pb, pa;  // the ends' positions
  std::uint32_t a, b;  // b collapses into a
  std::uint32_t stamp_a, stamp_b;  // the ends as they were when queued
  bool operator>(const CandidateRef& o) const {
    return std::tie(cost, length2, pb, pa, b, a) >
           std::tie(o.cost, o.length2, o.pb, o.pa, o.b, o.a);
  }
};

class CollapserRef {
 public:
  CollapserRef(const TriMesh& m, const std::vector<std::uint8_t>& locked, const CollapseParams& p)
      : p_(p), pos_(m.vertices), tri_(m.triangles) {
    const std::size_t nv = pos_.size();
    locked_ = locked.empty() ? std::vector<std::uint8_t>(nv, 0) : locked;
    quadric_.resize(nv);
    stamp_.assign(nv, 0);
    mark_.assign(nv, 0);
    dead_.assign(tri_.size(), 0);
    std::vector<std::uint32_t> degree(nv, 0);
    for (const auto& t : tri_)
      for (std::uint32_t v : t) ++degree[v];
    around_.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) around_[v].reserve(degree[v]);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      const auto& v = tri_[t];
      for (int c = 0; c < 3; ++c) around_[v[c]].push_back(std::uint32_t(t));
      const Vec3 n = normal_of(pos_[v[0]], pos_[v[1]], pos_[v[2]]);
      const double len = length(n);
      if (!(len > 0)) continue;
      const Vec3 u{n[0] / len, n[1] / len, n[2] / len};
      const Quadric q = Quadric::plane(u, -dot(u, pos_[v[0]]));
      for (int c = 0; c < 3; ++c) quadric_[v[c]] += q;
    }
    Vec3 lo{}, hi{};
    if (nv > 0) lo = hi = pos_[0];
    for (const Vec3& x : pos_)
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], x[c]), hi[c] = std::max(hi[c], x[c]);
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    noise_ = 1e-14 * extent * extent;
    cos_limit_ = std::cos(p_.max_normal_degrees * std::numbers::pi / 180.0);
    alive_ = tri_.size();
    std::vector<CandidateRef> initial;
    initial.reserve(tri_.size() * 3 / 2);
    for (const auto& t : tri_)
      for (int c = 0; c < 3; ++c)
        if (t[c] < t[(c + 1) % 3]) push(t[c], t[(c + 1) % 3], &initial);
    heap_ = decltype(heap_)(std::greater<CandidateRef>(), std::move(initial));
  }

  void run(const CollapseProgress& progress) {
    const double max_cost = p_.max_error * p_.max_error;
    std::size_t since = 0;
    while (!heap_.empty()) {
      if (p_.target_triangles > 0 && alive_ <= p_.target_triangles) break;
      const CandidateRef e = heap_.top();
      heap_.pop();
      if (stamp_[e.a] != e.stamp_a || stamp_[e.b] != e.stamp_b) continue;  // stale
      if (double(e.cost) > max_cost) break;
      Vec3 p;
      best_position(e.a, e.b, p);  // the same ends give the same position as when queued
      if (!legal(e.a, e.b, p)) continue;
      collapse(e.a, e.b, p);
      if (progress && ++since == (1u << 16)) {
        since = 0;
        progress(alive_);
      }
    }
  }

  TriMesh result() const {
    TriMesh r;
    std::vector<std::uint32_t> index(pos_.size(), UINT32_MAX);
    r.triangles.reserve(alive_);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      if (dead_[t]) continue;
      std::array<std::uint32_t, 3> out{};
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = tri_[t][c];
        if (index[v] == UINT32_MAX) {
          index[v] = std::uint32_t(r.vertices.size());
          r.vertices.push_back(pos_[v]);
        }
        out[c] = index[v];
      }
      r.triangles.push_back(out);
    }
    return r;
  }

 private:
  // The mean squared distance to the merged planes of collapsing w into u at its best
  // position p (u's own when u is locked; the quadric's minimiser when it lies near the
  // edge; else the better of the ends and the midpoint).
  double best_position(std::uint32_t u, std::uint32_t w, Vec3& best) const {
    Quadric q = quadric_[u];
    q += quadric_[w];
    const double per_plane = 1.0 / std::max(q.planes, 1.0);
    best = pos_[u];
    double cost = q(best);
    if (locked_[u]) return cost * per_plane;
    const Vec3 mid{0.5 * (pos_[u][0] + pos_[w][0]), 0.5 * (pos_[u][1] + pos_[w][1]),
                   0.5 * (pos_[u][2] + pos_[w][2])};
    Vec3 opt;
    // Far off the edge the minimiser marks a nearly flat quadric, not a better place.
    if (q.minimum(opt) && length(sub(opt, mid)) <= length(sub(pos_[u], pos_[w]))) {
      best = opt;
      return q(opt) * per_plane;
    }
    for (const Vec3& c : {pos_[w], mid})
      if (const double e = q(c); e < cost) cost = e, best = c;
    return cost * per_plane;
  }

  // Queues the collapse of edge (u, w); a locked end is the one kept.
  void push(std::uint32_t u, std::uint32_t w, std::vector<CandidateRef>* into = nullptr) {
    if (locked_[u] && locked_[w]) return;
    if (locked_[u] == 0 && locked_[w] != 0) std::swap(u, w);
    Vec3 p;
    const double cost = best_position(u, w, p);
    // Costs within round-off of 0 are 0: their signs and sizes followed the input's last bits.
    const Vec3 d = sub(pos_[u], pos_[w]);
    auto to_float = [](const Vec3& x) {
      return std::array<float, 3>{float(x[0]), float(x[1]), float(x[2])};
    };
    const CandidateRef c{cost > noise_ ? float(cost) : 0.0f, float(dot(d, d)), to_float(pos_[w]),
                      to_float(pos_[u]), u, w, stamp_[u], stamp_[w]};
    if (into) into->push_back(c);
    else heap_.push(c);
  }

  bool legal(std::uint32_t a, std::uint32_t b, const Vec3& p) {
    // The two triangles on the edge, and the link condition: a and b share exactly the two
    // vertices opposite the edge.
    std::uint32_t shared = 0, opposite[2] = {0, 0};
    for (std::uint32_t t : around_[b]) {
      const auto& v = tri_[t];
      if (v[0] != a && v[1] != a && v[2] != a) continue;
      if (shared == 2) return false;
      for (std::uint32_t x : v)
        if (x != a && x != b) opposite[shared] = x;
      ++shared;
    }
    if (shared != 2 || opposite[0] == opposite[1]) return false;
    if (around_[opposite[0]].size() <= 3 || around_[opposite[1]].size() <= 3) return false;
    if (around_[a].size() + around_[b].size() < 7) return false;  // the result's valence >= 3
    const std::uint32_t id = next_mark();
    for (std::uint32_t t : around_[a])
      for (std::uint32_t x : tri_[t]) mark_[x] = id;
    int common = 0;
    for (std::uint32_t t : around_[b])
      for (std::uint32_t x : tri_[t])
        if (x != a && x != b && mark_[x] == id) {
          mark_[x] = id + 1;
          ++common;
        }
    if (common != 2) return false;
    // The triangles that remain, moved: normals, areas, shapes; with an error bound, the
    // two old vertices (each within it of the input) stay within it of the new fan.
    const bool bounded = std::isfinite(p_.max_error);
    const double bound2 = p_.max_error * p_.max_error;
    double near_a = bounded ? std::numeric_limits<double>::infinity() : 0.0, near_b = near_a;
    for (const std::uint32_t moved : {a, b})
      for (std::uint32_t t : around_[moved]) {
        const auto& v = tri_[t];
        const bool on_edge = (v[0] == a || v[1] == a || v[2] == a) &&
                             (v[0] == b || v[1] == b || v[2] == b);
        if (on_edge) continue;
        Vec3 q[3];
        for (int c = 0; c < 3; ++c) q[c] = v[c] == moved ? p : pos_[v[c]];
        if (bounded) {
          near_a = std::min(near_a, point_triangle_distance2(pos_[a], q[0], q[1], q[2]));
          near_b = std::min(near_b, point_triangle_distance2(pos_[b], q[0], q[1], q[2]));
        }
        const Vec3 n0 = normal_of(pos_[v[0]], pos_[v[1]], pos_[v[2]]);
        const Vec3 n1 = normal_of(q[0], q[1], q[2]);
        const double l0 = length(n0), l1 = length(n1);
        if (!(l1 > 1e-12 * (l0 + dot(sub(q[1], q[0]), sub(q[1], q[0]))))) return false;
        if (l0 > 0 && dot(n0, n1) < cos_limit_ * l0 * l1) return false;
        const double aspect = triangle_aspect(q[0], q[1], q[2]);
        if (aspect > p_.max_aspect &&
            aspect > triangle_aspect(pos_[v[0]], pos_[v[1]], pos_[v[2]]))
          return false;
      }
    return near_a <= bound2 && near_b <= bound2;
  }

  void collapse(std::uint32_t a, std::uint32_t b, const Vec3& p) {
    std::vector<std::uint32_t>& ta = around_[a];
    std::uint32_t opposite[2] = {0, 0};
    int k = 0;
    for (std::uint32_t t : around_[b]) {
      auto& v = tri_[t];
      if (v[0] == a || v[1] == a || v[2] == a) {
        dead_[t] = 1;
        for (std::uint32_t x : v)
          if (x != a && x != b) opposite[k] = x;
        ++k;
      } else {
        for (auto& x : v)
          if (x == b) x = a;
        ta.push_back(t);
      }
    }
    auto drop_dead = [&](std::vector<std::uint32_t>& list) {
      list.erase(std::remove_if(list.begin(), list.end(),
                                [&](std::uint32_t t) { return dead_[t] != 0; }),
                 list.end());
    };
    drop_dead(ta);
    drop_dead(around_[opposite[0]]);
    drop_dead(around_[opposite[1]]);
    around_[b].clear();
    around_[b].shrink_to_fit();
    alive_ -= 2;
    pos_[a] = p;
    quadric_[a] += quadric_[b];
    ++stamp_[a];
    ++stamp_[b];
    const std::uint32_t id = next_mark();
    mark_[a] = id;
    for (std::uint32_t t : ta)
      for (std::uint32_t x : tri_[t])
        if (mark_[x] != id) {
          mark_[x] = id;
          push(a, x);
        }
  }

  std::uint32_t next_mark() {
    mark_id_ += 2;
    if (mark_id_ < 2) {  // wrapped
      std::fill(mark_.begin(), mark_.end(), 0);
      mark_id_ = 2;
    }
    return mark_id_;
  }

  CollapseParams p_;
  std::vector<Vec3> pos_;
  std::vector<std::array<std::uint32_t, 3>> tri_;
  std::vector<std::uint8_t> locked_, dead_;
  std::vector<Quadric> quadric_;
  std::vector<std::uint32_t> stamp_, mark_;
  std::uint32_t mark_id_ = 0;
  std::vector<std::vector<std::uint32_t>> around_;  // the live triangles at each vertex
  std::priority_queue<CandidateRef, std::vector<CandidateRef>, std::greater<CandidateRef>> heap_;
  std::size_t alive_ = 0;
  double cos_limit_ = 0.5;
  double noise_ = 0.0;  // squared distance: (1e-7 of the extent)^2
};

// The optimised collapser (collapse_edges): the reference's rules, costs, positions and order,
// with a 4-ary heap (non-negative floats order as their bits: cost and length are one integer
// compare), quadrics that may be handed in (the slabs' second pass continues the first's) and a
// tick that may stop it.

std::uint32_t float_bits(float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}

// Equal costs go shortest edge first, then by the ends' positions, never by index (the
// reference's rule and order, for the same reason: ordering ties at b by index instead of by
// a's position took a G network's error at a tenth of its triangles from under 0.02 to 0.024
// cells). The cost and length compare as one integer.
struct Candidate {
  std::uint64_t key;  // the cost's bits, then the squared length's
  std::array<float, 3> pb, pa;  // the ends' positions
  std::uint32_t a, b;  // b collapses into a
  std::uint32_t stamp_a, stamp_b;
  bool operator>(const Candidate& o) const {
    if (key != o.key) return key > o.key;
    return std::tie(pb, pa, b, a) > std::tie(o.pb, o.pa, o.b, o.a);
  }
};

// A 4-ary min-heap: half the depth of a binary one, and a node's children share cache lines
// (the queue of a large part is hundreds of MB, so its pops are memory-bound).
template <class T>
class QuadHeap {
 public:
  bool empty() const { return a_.empty(); }
  const T& top() const { return a_[0]; }
  void push(const T& x) {
    a_.push_back(x);
    up(a_.size() - 1);
  }
  void pop() {
    a_[0] = a_.back();
    a_.pop_back();
    if (!a_.empty()) down(0);
  }

 private:
  void up(std::size_t i) {
    const T x = a_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / 4;
      if (!(a_[parent] > x)) break;
      a_[i] = a_[parent];
      i = parent;
    }
    a_[i] = x;
  }
  void down(std::size_t i) {
    const T x = a_[i];
    const std::size_t n = a_.size();
    for (;;) {
      const std::size_t first = 4 * i + 1;
      if (first >= n) break;
      std::size_t best = first;
      for (std::size_t k = first + 1; k < std::min(first + 4, n); ++k)
        if (a_[best] > a_[k]) best = k;
      if (!(x > a_[best])) break;
      a_[i] = a_[best];
      i = best;
    }
    a_[i] = x;
  }
  std::vector<T> a_;
};

// Each vertex's sum of the planes of its triangles (unit normals), in triangle order.
std::vector<Quadric> plane_quadrics(const TriMesh& m) {
  std::vector<Quadric> q(m.vertices.size());
  for (const auto& v : m.triangles) {
    const Vec3 n = normal_of(m.vertices[v[0]], m.vertices[v[1]], m.vertices[v[2]]);
    const double len = length(n);
    if (!(len > 0)) continue;
    const Vec3 u{n[0] / len, n[1] / len, n[2] / len};
    const Quadric plane = Quadric::plane(u, -dot(u, m.vertices[v[0]]));
    for (int c = 0; c < 3; ++c) q[v[c]] += plane;
  }
  return q;
}

class Collapser {
 public:
  // extent: the whole part's largest box side (a slab's own would change the rounding rule).
  // seeds: the vertices whose edges are queued first (empty: every edge).
  Collapser(const TriMesh& m, const std::vector<std::uint8_t>& locked, const CollapseParams& p,
            std::vector<Quadric> quadrics, double extent,
            const std::vector<std::uint8_t>& seeds = {})
      : p_(p), pos_(m.vertices), tri_(m.triangles), quadric_(std::move(quadrics)) {
    const std::size_t nv = pos_.size();
    locked_ = locked.empty() ? std::vector<std::uint8_t>(nv, 0) : locked;
    if (quadric_.empty()) quadric_ = plane_quadrics(m);
    stamp_.assign(nv, 0);
    mark_.assign(nv, 0);
    dead_.assign(tri_.size(), 0);
    std::vector<std::uint32_t> degree(nv, 0);
    for (const auto& t : tri_)
      for (std::uint32_t v : t) ++degree[v];
    around_.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) around_[v].reserve(degree[v]);
    for (std::size_t t = 0; t < tri_.size(); ++t)
      for (int c = 0; c < 3; ++c) around_[tri_[t][c]].push_back(std::uint32_t(t));
    noise_ = 1e-14 * extent * extent;
    cos_limit_ = std::cos(p_.max_normal_degrees * std::numbers::pi / 180.0);
    alive_ = tri_.size();
    queue_edges(seeds);
  }

  // Queues the live edges with an end in seeds (empty: all). An edge refused once is queued
  // again only when a collapse moves one of its ends, as in the reference; queueing all of
  // them again retries every refusal, more collapses than the reference makes (measured: a
  // second pass over all edges took the 10 mm part's error from under 0.01 mm to 0.0107).
  void queue_edges(const std::vector<std::uint8_t>& seeds = {}) {
    std::vector<Candidate> initial;
    initial.reserve(seeds.empty() ? tri_.size() * 3 / 2 : 0);
    for (std::size_t t = 0; t < tri_.size(); ++t) {
      if (dead_[t]) continue;
      const auto& v = tri_[t];
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = v[c], b = v[(c + 1) % 3];
        if (a < b && (seeds.empty() || seeds[a] || seeds[b])) push(a, b, &initial);
      }
    }
    for (const Candidate& e : initial) heap_.push(e);
  }

  // Collapses down to target triangles (0: no budget) or the error bound; tick() every
  // kTick collapses, false: stop.
  static constexpr std::size_t kTick = 4096;
  template <class Tick>
  void run(std::size_t target, Tick&& tick) {
    const double max_cost = p_.max_error * p_.max_error;
    std::size_t since = 0;
    while (!heap_.empty()) {
      if (target > 0 && alive_ <= target) break;
      const Candidate e = heap_.top();
      heap_.pop();
      if (stamp_[e.a] != e.stamp_a || stamp_[e.b] != e.stamp_b) continue;  // stale
      if (double(cost_of(e)) > max_cost) break;
      Vec3 p;
      best_position(e.a, e.b, p);  // the same ends give the same position as when queued
      if (!legal(e.a, e.b, p)) continue;
      collapse(e.a, e.b, p);
      if (++since == kTick) {
        since = 0;
        if (!tick()) break;
      }
    }
  }

  std::size_t alive() const { return alive_; }
  const std::vector<Vec3>& positions() const { return pos_; }
  const std::vector<Quadric>& quadrics() const { return quadric_; }
  template <class F>
  void for_each_live(F&& f) const {
    for (std::size_t t = 0; t < tri_.size(); ++t)
      if (!dead_[t]) f(tri_[t]);
  }

  TriMesh result() const {
    TriMesh r;
    std::vector<std::uint32_t> index(pos_.size(), UINT32_MAX);
    r.triangles.reserve(alive_);
    for_each_live([&](const std::array<std::uint32_t, 3>& t) {
      std::array<std::uint32_t, 3> out{};
      for (int c = 0; c < 3; ++c) {
        if (index[t[c]] == UINT32_MAX) {
          index[t[c]] = std::uint32_t(r.vertices.size());
          r.vertices.push_back(pos_[t[c]]);
        }
        out[c] = index[t[c]];
      }
      r.triangles.push_back(out);
    });
    return r;
  }

 private:
  static float cost_of(const Candidate& e) {
    const std::uint32_t bits = std::uint32_t(e.key >> 32);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }

  // As the reference's best_position; u's own cost is evaluated only where it is used.
  double best_position(std::uint32_t u, std::uint32_t w, Vec3& best) const {
    Quadric q = quadric_[u];
    q += quadric_[w];
    const double per_plane = 1.0 / std::max(q.planes, 1.0);
    best = pos_[u];
    if (locked_[u]) return q(best) * per_plane;
    const Vec3 mid{0.5 * (pos_[u][0] + pos_[w][0]), 0.5 * (pos_[u][1] + pos_[w][1]),
                   0.5 * (pos_[u][2] + pos_[w][2])};
    Vec3 opt;
    if (q.minimum(opt) && length(sub(opt, mid)) <= length(sub(pos_[u], pos_[w]))) {
      best = opt;
      return q(opt) * per_plane;
    }
    double cost = q(best);
    for (const Vec3& c : {pos_[w], mid})
      if (const double e = q(c); e < cost) cost = e, best = c;
    return cost * per_plane;
  }

  void push(std::uint32_t u, std::uint32_t w, std::vector<Candidate>* into = nullptr) {
    if (locked_[u] && locked_[w]) return;
    if (locked_[u] == 0 && locked_[w] != 0) std::swap(u, w);
    Vec3 p;
    const double cost = best_position(u, w, p);
    const Vec3 d = sub(pos_[u], pos_[w]);
    const float c = cost > noise_ ? float(cost) : 0.0f;
    const Candidate e{(std::uint64_t(float_bits(c)) << 32) | float_bits(float(dot(d, d))),
                      {float(pos_[w][0]), float(pos_[w][1]), float(pos_[w][2])},
                      {float(pos_[u][0]), float(pos_[u][1]), float(pos_[u][2])},
                      u, w, stamp_[u], stamp_[w]};
    if (into) into->push_back(e);
    else heap_.push(e);
  }

  // As the reference's.
  bool legal(std::uint32_t a, std::uint32_t b, const Vec3& p) {
    // The two triangles on the edge, and the link condition: a and b share exactly the two
    // vertices opposite the edge.
    std::uint32_t shared = 0, opposite[2] = {0, 0};
    for (std::uint32_t t : around_[b]) {
      const auto& v = tri_[t];
      if (v[0] != a && v[1] != a && v[2] != a) continue;
      if (shared == 2) return false;
      for (std::uint32_t x : v)
        if (x != a && x != b) opposite[shared] = x;
      ++shared;
    }
    if (shared != 2 || opposite[0] == opposite[1]) return false;
    if (around_[opposite[0]].size() <= 3 || around_[opposite[1]].size() <= 3) return false;
    if (around_[a].size() + around_[b].size() < 7) return false;  // the result's valence >= 3
    const std::uint32_t id = next_mark();
    for (std::uint32_t t : around_[a])
      for (std::uint32_t x : tri_[t]) mark_[x] = id;
    int common = 0;
    for (std::uint32_t t : around_[b])
      for (std::uint32_t x : tri_[t])
        if (x != a && x != b && mark_[x] == id) {
          mark_[x] = id + 1;
          ++common;
        }
    if (common != 2) return false;
    // The triangles that remain, moved: normals, areas, shapes; with an error bound, the
    // two old vertices (each within it of the input) stay within it of the new fan.
    const bool bounded = std::isfinite(p_.max_error);
    const double bound2 = p_.max_error * p_.max_error;
    double near_a = bounded ? std::numeric_limits<double>::infinity() : 0.0, near_b = near_a;
    for (const std::uint32_t moved : {a, b})
      for (std::uint32_t t : around_[moved]) {
        const auto& v = tri_[t];
        const bool on_edge = (v[0] == a || v[1] == a || v[2] == a) &&
                             (v[0] == b || v[1] == b || v[2] == b);
        if (on_edge) continue;
        Vec3 q[3];
        for (int c = 0; c < 3; ++c) q[c] = v[c] == moved ? p : pos_[v[c]];
        if (bounded) {
          near_a = std::min(near_a, point_triangle_distance2(pos_[a], q[0], q[1], q[2]));
          near_b = std::min(near_b, point_triangle_distance2(pos_[b], q[0], q[1], q[2]));
        }
        const Vec3 n0 = normal_of(pos_[v[0]], pos_[v[1]], pos_[v[2]]);
        const Vec3 n1 = normal_of(q[0], q[1], q[2]);
        const double l0 = length(n0), l1 = length(n1);
        if (!(l1 > 1e-12 * (l0 + dot(sub(q[1], q[0]), sub(q[1], q[0]))))) return false;
        if (l0 > 0 && dot(n0, n1) < cos_limit_ * l0 * l1) return false;
        const double aspect = triangle_aspect(q[0], q[1], q[2]);
        if (aspect > p_.max_aspect &&
            aspect > triangle_aspect(pos_[v[0]], pos_[v[1]], pos_[v[2]]))
          return false;
      }
    return near_a <= bound2 && near_b <= bound2;
  }

  void collapse(std::uint32_t a, std::uint32_t b, const Vec3& p) {
    std::vector<std::uint32_t>& ta = around_[a];
    std::uint32_t opposite[2] = {0, 0};
    int k = 0;
    for (std::uint32_t t : around_[b]) {
      auto& v = tri_[t];
      if (v[0] == a || v[1] == a || v[2] == a) {
        dead_[t] = 1;
        for (std::uint32_t x : v)
          if (x != a && x != b) opposite[k] = x;
        ++k;
      } else {
        for (auto& x : v)
          if (x == b) x = a;
        ta.push_back(t);
      }
    }
    auto drop_dead = [&](std::vector<std::uint32_t>& list) {
      list.erase(std::remove_if(list.begin(), list.end(),
                                [&](std::uint32_t t) { return dead_[t] != 0; }),
                 list.end());
    };
    drop_dead(ta);
    drop_dead(around_[opposite[0]]);
    drop_dead(around_[opposite[1]]);
    // Cleared, not freed: a free per collapse cost more than the memory, held from the start.
    around_[b].clear();
    alive_ -= 2;
    pos_[a] = p;
    quadric_[a] += quadric_[b];
    ++stamp_[a];
    ++stamp_[b];
    const std::uint32_t id = next_mark();
    mark_[a] = id;
    for (std::uint32_t t : ta)
      for (std::uint32_t x : tri_[t])
        if (mark_[x] != id) {
          mark_[x] = id;
          push(a, x);
        }
  }

  std::uint32_t next_mark() {
    mark_id_ += 2;
    if (mark_id_ < 2) {  // wrapped
      std::fill(mark_.begin(), mark_.end(), 0);
      mark_id_ = 2;
    }
    return mark_id_;
  }

  CollapseParams p_;
  std::vector<Vec3> pos_;
  std::vector<std::array<std::uint32_t, 3>> tri_;
  std::vector<std::uint8_t> locked_, dead_;
  std::vector<Quadric> quadric_;
  std::vector<std::uint32_t> stamp_, mark_;
  std::uint32_t mark_id_ = 0;
  std::vector<std::vector<std::uint32_t>> around_;  // the live triangles at each vertex
  QuadHeap<Candidate> heap_;
  std::size_t alive_ = 0;
  double cos_limit_ = 0.5;
  double noise_ = 0.0;
};

// Calls a CollapseProgress from the threads' collapses: the sum of their collapses kept
// atomically, the callback only on the first thread (every kEvery ticks), and an exception from
// it (a stop asked for) kept and rethrown after the parallel region, with every slab stopped.
class SharedProgress {
 public:
  SharedProgress(const CollapseProgress& progress, std::size_t triangles)
      : progress_(progress), triangles_(triangles) {}
  bool tick() {
    removed_ += 2 * Collapser::kTick;
    if (stop_) return false;
    if (!progress_ || omp_get_thread_num() != 0 || ++ticks_ % kEvery != 0) return true;
    try {
      const std::size_t removed = removed_;
      progress_(triangles_ - std::min(removed, triangles_));
    } catch (...) {
      error_ = std::current_exception();
      stop_ = true;
    }
    return !stop_;
  }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  static constexpr std::size_t kEvery = 16;
  const CollapseProgress& progress_;
  std::size_t triangles_;
  std::atomic<std::size_t> removed_{0};
  std::atomic<bool> stop_{false};
  std::size_t ticks_ = 0;  // the first thread's only
  std::exception_ptr error_;
};

double box_extent(const TriMesh& m, int* axis = nullptr) {
  const MeshStats box = bounding_box(m);
  int longest = 0;
  for (int c = 1; c < 3; ++c)
    if (box.max[c] - box.min[c] > box.max[longest] - box.min[longest]) longest = c;
  if (axis) *axis = longest;
  return box.max[longest] - box.min[longest];
}

// The slabs' first pass. The triangles are cut along the box's longest axis into slabs of
// equal triangle counts (by their centroids). A vertex whose triangles lie in two slabs, and
// every neighbour of it, stays in place there: then a slab's free vertex has its triangles and
// its neighbours' triangles in that slab alone, so no two slabs touch the same triangle or
// vertex and each slab's link conditions see whole rings. Each slab collapses to its share of
// the budget (or the error bound) on its own thread; the second pass, serial, continues from
// the slabs' quadrics over the whole mesh (the seams). The slabs are set by the input alone,
// so the result does not depend on the number of threads.
TriMesh collapse_in_slabs(const TriMesh& m, const std::vector<std::uint8_t>& locked,
                          const CollapseParams& p, int slabs, const CollapseProgress& progress) {
  const std::size_t nt = m.triangles.size(), nv = m.vertices.size();
  int axis = 0;
  const double extent = box_extent(m, &axis);
  std::vector<double> along(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = m.triangles[t];
    along[t] = m.vertices[v[0]][axis] + m.vertices[v[1]][axis] + m.vertices[v[2]][axis];
  }
  std::vector<double> cuts(slabs - 1);
  {
    std::vector<double> sorted = along;
    for (int k = 1; k < slabs; ++k) {
      auto at = sorted.begin() + std::ptrdiff_t(nt * k / slabs);
      std::nth_element(sorted.begin(), at, sorted.end());
      cuts[k - 1] = *at;
    }
    std::sort(cuts.begin(), cuts.end());
  }
  std::vector<std::uint32_t> owner(nt);
  std::vector<std::vector<std::uint32_t>> owned(slabs);
  for (std::size_t t = 0; t < nt; ++t) {
    owner[t] = std::uint32_t(std::upper_bound(cuts.begin(), cuts.end(), along[t]) - cuts.begin());
    owned[owner[t]].push_back(std::uint32_t(t));
  }
  std::vector<std::uint32_t> vertex_slab(nv, UINT32_MAX);
  std::vector<std::uint8_t> seam(nv, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (std::uint32_t v : m.triangles[t]) {
      if (vertex_slab[v] == UINT32_MAX) vertex_slab[v] = owner[t];
      else if (vertex_slab[v] != owner[t]) seam[v] = 1;
    }
  std::vector<std::uint8_t> frozen = locked.empty() ? std::vector<std::uint8_t>(nv, 0) : locked;
  std::vector<std::uint8_t> band(nv, 0);  // frozen here, free in the second pass
  for (const auto& t : m.triangles)
    if (seam[t[0]] || seam[t[1]] || seam[t[2]])
      for (std::uint32_t v : t) band[v] = locked.empty() || !locked[v];
  for (std::size_t v = 0; v < nv; ++v) frozen[v] |= band[v];

  std::vector<Quadric> quadrics = plane_quadrics(m);
  std::vector<Vec3> pos = m.vertices;
  std::vector<std::vector<std::array<std::uint32_t, 3>>> kept(slabs);
  SharedProgress shared(progress, nt);
#pragma omp parallel
  {
    std::vector<std::uint32_t> local(nv, UINT32_MAX);
#pragma omp for schedule(dynamic, 1)
    for (int s = 0; s < slabs; ++s) {
      TriMesh sub;
      std::vector<std::uint32_t> global;
      std::vector<std::uint8_t> sub_locked;
      std::vector<Quadric> sub_quadrics;
      sub.triangles.reserve(owned[s].size());
      for (std::uint32_t t : owned[s]) {
        std::array<std::uint32_t, 3> out{};
        for (int c = 0; c < 3; ++c) {
          const std::uint32_t v = m.triangles[t][c];
          if (local[v] == UINT32_MAX) {
            local[v] = std::uint32_t(global.size());
            global.push_back(v);
            sub.vertices.push_back(m.vertices[v]);
            sub_locked.push_back(frozen[v]);
            sub_quadrics.push_back(quadrics[v]);
          }
          out[c] = local[v];
        }
        sub.triangles.push_back(out);
      }
      for (std::uint32_t v : global) local[v] = UINT32_MAX;
      // With a budget, the slab's free triangles go to the budget's share and its seams'
      // stay for the second pass (their share of the whole slab's would over-collapse the
      // rest: measured 2.4 % of the volume lost on a 20k-triangle network in 4 slabs).
      std::size_t target = 0;
      if (p.target_triangles > 0) {
        std::size_t seams = 0;
        for (const auto& t : sub.triangles)
          seams += band[global[t[0]]] || band[global[t[1]]] || band[global[t[2]]];
        const double ratio = double(p.target_triangles) / double(nt);
        target = std::max<std::size_t>(
            1, seams + std::size_t(ratio * double(sub.triangles.size() - seams)));
      }
      Collapser c(sub, sub_locked, p, std::move(sub_quadrics), extent);
      c.run(target, [&] { return shared.tick(); });
      // Seam vertices are in several slabs and unchanged in each; the others in this one.
      for (std::size_t k = 0; k < global.size(); ++k)
        if (!seam[global[k]]) {
          pos[global[k]] = c.positions()[k];
          quadrics[global[k]] = c.quadrics()[k];
        }
      kept[s].reserve(c.alive());
      c.for_each_live([&](const std::array<std::uint32_t, 3>& t) {
        kept[s].push_back({global[t[0]], global[t[1]], global[t[2]]});
      });
    }
  }
  shared.rethrow();

  // The second pass over the slabs' triangles, unused vertices dropped.
  TriMesh joined;
  std::vector<std::uint32_t> index(nv, UINT32_MAX);
  std::vector<std::uint8_t> joined_locked, joined_band;
  std::vector<Quadric> joined_quadrics;
  for (const auto& list : kept)
    for (const auto& t : list) {
      std::array<std::uint32_t, 3> out{};
      for (int c = 0; c < 3; ++c) {
        if (index[t[c]] == UINT32_MAX) {
          index[t[c]] = std::uint32_t(joined.vertices.size());
          joined.vertices.push_back(pos[t[c]]);
          joined_locked.push_back(locked.empty() ? 0 : locked[t[c]]);
          joined_band.push_back(band[t[c]]);
          joined_quadrics.push_back(quadrics[t[c]]);
        }
        out[c] = index[t[c]];
      }
      joined.triangles.push_back(out);
    }
  kept.clear();
  // The seams' edges first; the rest only where the budget is not met by then.
  Collapser c(joined, joined_locked, p, std::move(joined_quadrics), extent, joined_band);
  std::size_t ticks = 0;
  const auto tick = [&] {
    if (progress && ++ticks % 16 == 0) progress(c.alive());
    return true;
  };
  c.run(p.target_triangles, tick);
  if (p.target_triangles > 0 && c.alive() > p.target_triangles) {
    c.queue_edges();
    c.run(p.target_triangles, tick);
  }
  return c.result();
}

}  // namespace

double triangle_aspect(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = length(sub(b, a)), bc = length(sub(c, b)), ca = length(sub(a, c));
  const double area = 0.5 * length(normal_of(a, b, c));
  if (!(area > 0)) return std::numeric_limits<double>::infinity();
  const double inradius = 2.0 * area / (ab + bc + ca);
  return std::max({ab, bc, ca}) / (2.0 * std::sqrt(3.0) * inradius);
}

TriMesh collapse_edges_ref(const TriMesh& m, const std::vector<std::uint8_t>& locked,
                           const CollapseParams& p, const CollapseProgress& progress) {
  CollapserRef c(m, locked, p);
  c.run(progress);
  return c.result();
}

TriMesh collapse_edges(const TriMesh& m, const std::vector<std::uint8_t>& locked,
                       const CollapseParams& p, const CollapseProgress& progress) {
  const int slabs =
      p.slabs > 0 ? p.slabs
                  : int(std::min<std::size_t>(kMaxSlabs, m.triangles.size() / kSlabTriangles));
  if (slabs >= 2) return collapse_in_slabs(m, locked, p, slabs, progress);
  Collapser c(m, locked, p, {}, box_extent(m));
  std::size_t ticks = 0;
  c.run(p.target_triangles, [&] {
    if (progress && ++ticks % 16 == 0) progress(c.alive());
    return true;
  });
  return c.result();
}

}  // namespace cmcsurf
