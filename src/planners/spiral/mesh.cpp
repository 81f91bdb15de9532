// The one translation unit of the spiral planner that includes CGAL.
#include "planners/spiral/mesh.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_voronoi_diagram_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_2/Lloyd_move_2.h>
#include <CGAL/Mesh_2/Uniform_sizing_field_2.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/lloyd_optimize_mesh_2.h>
#include <CGAL/property_map.h>

#include <boost/geometry/algorithms/point_on_surface.hpp>

#include <chrono>
#include <cmath>
#include <ctime>
#include <string>
#include <unordered_map>
#include <utility>

#include "uavcover/error.hpp"

namespace uavcover::planners::spiral {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

/// A base with a time stamp: CGAL then orders handles (std::set, std::map inside the mesher and
/// Lloyd) by creation, not by address, which makes the mesh the same from run to run. CGAL's own
/// mesh bases have stamps only in debug builds (CGAL_MESH_2_DEBUG_REFINEMENT_POINTS).
template <class Base>
struct Stamped : Base {
  template <typename TDS2>
  struct Rebind_TDS {
    using Other = Stamped<typename Base::template Rebind_TDS<TDS2>::Other>;
  };
  // user-provided constructors that leave the stamp alone: the container sets it to -1 before
  // constructing an element in place and stamps it after (value-initialisation of an aggregate-like
  // default constructor would zero it, and every handle would compare equal)
  Stamped() : Base() {}  // NOLINT(cppcoreguidelines-pro-type-member-init)
  template <typename A, typename... Rest>
  explicit Stamped(A&& a, Rest&&... rest) : Base(std::forward<A>(a), std::forward<Rest>(rest)...) {}
  using Has_timestamp = CGAL::Tag_true;
  [[nodiscard]] std::size_t time_stamp() const { return stamp_; }
  void set_time_stamp(const std::size_t& ts) { stamp_ = ts; }

 private:
  std::size_t stamp_;
};
using Vb = Stamped<CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = Stamped<CGAL::Delaunay_mesh_face_base_2<K>>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
using Mesher = CGAL::Delaunay_mesher_2<CDT, Criteria>;
using CPoint = CDT::Point;

using Density = CGAL::Mesh_2::Uniform_sizing_field_2<CDT>;
using LloydMove = CGAL::Mesh_2::Lloyd_move_2<CDT, Density>;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
/// This thread's CPU time (s): the machine may be shared, so the benchmarks report both.
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void insert_ring(CDT& cdt, const Polygon::ring_type& ring) {
  // closed ring: the last vertex repeats the first
  CDT::Vertex_handle first, prev;
  for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
    const auto v = cdt.insert(CPoint(ring[i].x(), ring[i].y()));
    if (i == 0)
      first = v;
    else if (v != prev)
      cdt.insert_constraint(prev, v);
    prev = v;
  }
  if (first != CDT::Vertex_handle() && prev != first) cdt.insert_constraint(prev, first);
}

std::size_t domain_faces(const CDT& cdt) {
  std::size_t n = 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain()) ++n;
  return n;
}

Mesh extract(const CDT& cdt) {
  Mesh m;
  std::unordered_map<CDT::Vertex_handle, int> vid;
  std::unordered_map<CDT::Face_handle, int> fid;
  // faces in the triangulation's (deterministic) iteration order
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    const int id = static_cast<int>(m.triangles.size());
    fid.emplace(f, id);
    std::array<int, 3> tri{};
    for (int i = 0; i < 3; ++i) {
      const auto v = f->vertex(i);
      auto [it, added] = vid.emplace(v, static_cast<int>(m.vertices.size()));
      if (added) m.vertices.emplace_back(v->point().x(), v->point().y());
      tri[static_cast<std::size_t>(i)] = it->second;
    }
    m.triangles.push_back(tri);
  }
  m.neighbours.assign(m.triangles.size(), {-1, -1, -1});
  for (const auto& [f, id] : fid)
    for (int i = 0; i < 3; ++i) {
      const auto n = f->neighbor(i);
      if (cdt.is_infinite(n) || !n->is_in_domain()) continue;
      const auto it = fid.find(n);
      if (it != fid.end())
        m.neighbours[static_cast<std::size_t>(id)][static_cast<std::size_t>(i)] = it->second;
    }
  return m;
}

/// The vertices Lloyd moves: those without an incident constraint (CGAL's rule), along a Hilbert
/// curve (CGAL::hilbert_sort, deterministic) so that consecutive moves touch faces already in cache
/// (in creation order 80 % of a step waited on memory). They keep that property while they move, so
/// the list is made once and updated when a vertex is re-inserted.
std::vector<CDT::Vertex_handle> free_vertices(const CDT& cdt) {
  using Item = std::pair<CPoint, CDT::Vertex_handle>;
  std::vector<Item> items;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (!cdt.are_there_incident_constraints(v)) items.emplace_back(v->point(), v);
  CGAL::hilbert_sort(items.begin(), items.end(),
                     CGAL::Spatial_sort_traits_adapter_2<K, CGAL::First_of_pair_property_map<Item>>());
  std::vector<CDT::Vertex_handle> out;
  out.reserve(items.size());
  for (const auto& [p, v] : items) out.push_back(v);
  return out;
}

/// The centroid of v's Voronoi cell restricted by the constraints (uniform density). Where no incident
/// face is blind (its circumcentre seen from it across no constraint), the cell is the polygon of
/// the incident faces' circumcentres; otherwise CGAL's Lloyd_move_2 clips it (CGAL::dual).
CPoint cell_centroid(const CDT& cdt, CDT::Vertex_handle v, const Density& density) {
  const CPoint& p = v->point();
  auto f = cdt.incident_faces(v);
  const auto f0 = f;
  bool plain = true;
  do plain = !cdt.is_infinite(f) && !f->is_blind();
  while (plain && ++f != f0);
  if (!plain) return p + LloydMove()(v, cdt, density);
  // fan of triangles (p, c_i, c_i+1) over consecutive circumcentres, counter-clockwise
  double area = 0.0, cx = 0.0, cy = 0.0;
  CPoint first = cdt.circumcenter(f), prev = first;
  while (++f != f0) {
    const CPoint c = cdt.circumcenter(f);
    const double a = (prev.x() - p.x()) * (c.y() - p.y()) - (prev.y() - p.y()) * (c.x() - p.x());
    area += a, cx += a * (p.x() + prev.x() + c.x()), cy += a * (p.y() + prev.y() + c.y());
    prev = c;
  }
  const double a = (prev.x() - p.x()) * (first.y() - p.y()) - (prev.y() - p.y()) * (first.x() - p.x());
  area += a, cx += a * (p.x() + prev.x() + first.x()), cy += a * (p.y() + prev.y() + first.y());
  if (!(area > 0.0)) return p;
  return {cx / (3.0 * area), cy / (3.0 * area)};
}

/// One Lloyd step on the triangulation itself (Jacobi, like CGAL's optimiser): every free vertex moves
/// to its cell's centroid. A move that keeps every incident triangle counter-clockwise sets the point
/// and restores the Delaunay property by Lawson flips from the vertex's star; any other is a removal
/// and an insertion located from a neighbouring face. ctx.check() every 1024 vertices.
void lloyd_step(CDT& cdt, std::vector<CDT::Vertex_handle>& movable, const std::vector<CPoint>& seeds,
                const Context& ctx) {
  CGAL::Constrained_voronoi_diagram_2<CDT>(cdt).tag_faces_blind();
  const Density density(cdt);
  std::vector<CPoint> target(movable.size());
  for (std::size_t i = 0; i < movable.size(); ++i) {
    if ((i + 1) % 1024 == 0) ctx.check();
    target[i] = cell_centroid(cdt, movable[i], density);
  }
  bool reinserted = false;
  std::vector<CDT::Edge> stack;
  for (std::size_t i = 0; i < movable.size(); ++i) {
    if ((i + 1) % 1024 == 0) ctx.check();
    const auto v = movable[i];
    const CPoint& p = target[i];
    if (p == v->point()) continue;
    // does p stay inside the kernel of v's star (every incident triangle keeps its orientation)?
    bool inside = true;
    auto f = cdt.incident_faces(v);
    const auto f0 = f;
    do {
      const int j = f->index(v);
      inside = !cdt.is_infinite(f) && CGAL::orientation(p, f->vertex(CDT::ccw(j))->point(),
                                                        f->vertex(CDT::cw(j))->point()) == CGAL::LEFT_TURN;
    } while (inside && ++f != f0);
    if (!inside) {
      const CDT::Face_handle hint = v->face()->neighbor(v->face()->index(v));
      cdt.remove(v);
      movable[i] = cdt.insert(p, hint);
      reinserted = true;
      continue;
    }
    v->set_point(p);
    // Lawson flips from every edge of the star (spokes and link) until all are locally Delaunay
    stack.clear();
    do {
      const int j = f->index(v);
      stack.emplace_back(f, j);
      stack.emplace_back(f, CDT::ccw(j));
    } while (++f != f0);
    while (!stack.empty()) {
      auto [g, k] = stack.back();
      stack.pop_back();
      if (cdt.is_infinite(g) || cdt.is_infinite(g->neighbor(k)) || !cdt.is_flipable(g, k)) continue;
      const auto n = g->neighbor(k);
      cdt.flip(g, k);  // g and n are now the two new triangles; their outer edges may need a flip
      for (const auto& h : {g, n})
        for (int e = 0; e < 3; ++e) stack.emplace_back(h, e);
    }
  }
  // flips keep each face's domain mark; faces made by a re-insertion need the marks again
  if (reinserted) Mesher::mark_facets(cdt, seeds.begin(), seeds.end(), true);
}

}  // namespace

Mesh build_mesh(const MultiPolygon& free, const MeshOptions& options, const Context& ctx,
                MeshReport& report) {
  CDT cdt;
  std::vector<CPoint> seeds;  // one point inside each free polygon: the meshed components
  for (const auto& poly : free) {
    insert_ring(cdt, poly.outer());
    for (const auto& in : poly.inners()) insert_ring(cdt, in);
    Point inside;
    bg::point_on_surface(poly, inside);
    seeds.emplace_back(inside.x(), inside.y());
  }
  ctx.check();

  const auto t0 = Clock::now();
  // shape bound 0.125: smallest angle about 20.7 degrees (CGAL's default); size bound: longest edge
  auto refine = [&] {
    Mesher mesher(cdt, Criteria(0.125, options.max_edge_m));
    mesher.set_seeds(seeds.begin(), seeds.end(), true);  // faces connected to a seed are the domain
    mesher.init();
    std::size_t steps = 0;
    while (!mesher.is_refinement_done()) {
      mesher.step_by_step_refine_mesh();
      if (++steps % 1024 == 0) {
        ctx.check();
        // about two faces per vertex: stop before the mesh grows past the bound
        if (options.max_triangles > 0 && 2 * cdt.number_of_vertices() > options.max_triangles + 1024)
          throw InputError("spacing_m", "the spiral mesh would need more than " +
                                            std::to_string(options.max_triangles) +
                                            " triangles; use a larger spacing or a smaller area");
      }
    }
  };
  refine();
  report.refine_s = since(t0);
  Mesh mesh = extract(cdt);
  report.triangles_before_lloyd = mesh.triangles.size();
  report.before_lloyd = angle_stats(mesh);

  const auto t1 = Clock::now();
  const double cpu1 = thread_cpu_s();
  if (options.lloyd == LloydMethod::Cgal) {
    // CGAL's global optimiser, one step per call (no convergence test, nothing frozen) so that a stop
    // lands between steps. Super-linear: each step keeps its largest moves in a sorted std::list of
    // n/100 entries searched linearly per vertex, and re-inserts each vertex with an unhinted locate.
    // A step cannot be interrupted, so the mesh is bounded to keep one step short (kMaxCgalLloydTriangles).
    if (options.lloyd_iterations > 0 && mesh.triangles.size() > kMaxCgalLloydTriangles)
      throw InputError("planner_params.lloyd_method",
                       "\"cgal\" runs uninterruptible Lloyd steps and is limited to " +
                           std::to_string(kMaxCgalLloydTriangles) + " triangles; this mesh has " +
                           std::to_string(mesh.triangles.size()) +
                           "; use \"local\" (the default), a larger spacing or lloyd_iterations 0");
    for (int i = 0; i < options.lloyd_iterations; ++i) {
      ctx.report("spiral", 0.05 + 0.35 * i / options.lloyd_iterations);
      ctx.check();
      CGAL::lloyd_optimize_mesh_2(cdt, CGAL::parameters::max_iteration_number = 1,
                                  CGAL::parameters::convergence = 0.0, CGAL::parameters::freeze_bound = 0.0,
                                  CGAL::parameters::seeds_begin = seeds.begin(),
                                  CGAL::parameters::seeds_end = seeds.end(), CGAL::parameters::mark = true);
    }
  } else {
    std::vector<CDT::Vertex_handle> movable;
    if (options.lloyd_iterations > 0) movable = free_vertices(cdt);
    for (int i = 0; i < options.lloyd_iterations; ++i) {
      ctx.report("spiral", 0.05 + 0.35 * i / options.lloyd_iterations);
      lloyd_step(cdt, movable, seeds, ctx);
    }
  }
  report.lloyd_s = since(t1);
  report.lloyd_cpu_s = thread_cpu_s() - cpu1;
  if (options.lloyd_iterations > 0) {
    // Lloyd moves vertices and may stretch some edges past the bound: refine again (it only adds points)
    refine();
    mesh = extract(cdt);
  }
  report.after_lloyd = angle_stats(mesh);
  report.max_edge_m = longest_edge(mesh);
  if (options.max_triangles > 0 && domain_faces(cdt) > options.max_triangles)
    throw InputError("spacing_m", "the spiral mesh would need more than " +
                                      std::to_string(options.max_triangles) +
                                      " triangles; use a larger spacing or a smaller area");
  return mesh;
}

}  // namespace uavcover::planners::spiral
