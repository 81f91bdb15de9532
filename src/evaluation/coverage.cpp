// Coverage simulation on a lattice (Apostolidis et al. 2022 §3.1): scanline fill of the free area,
// one oriented rectangle per straight leg rasterised row by row, scan counts per sample.
#include "evaluation/coverage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "photo/oblique.hpp"
#include "uavcover/error.hpp"

namespace uavcover::evaluation {

namespace {

struct Lattice {
  double s = 1.0;
  double x0 = 0.0, y0 = 0.0;  // centre of sample (0,0)
  int cols = 0, rows = 0;
};

/// Adaptive spacing: about one million samples, clamped to 0.5-2 m (0.25-4 m^2 per sample, as the
/// paper), then widened until the bounding box holds at most `max_samples`.
Lattice make_lattice(const bg::model::box<Point>& box, double area, const CoverageOptions& o) {
  const double bw = box.max_corner().x() - box.min_corner().x();
  const double bh = box.max_corner().y() - box.min_corner().y();
  double s = o.lattice_m;
  if (!(s > 0.0)) s = std::clamp(std::sqrt(std::max(area, 1.0) / 1.0e6), 0.5, 2.0);
  const double cap = static_cast<double>(std::max<std::size_t>(o.max_samples, 1));
  while (std::max(1.0, std::ceil(bw / s)) * std::max(1.0, std::ceil(bh / s)) > cap) s *= 1.05;
  Lattice l;
  l.s = s;
  l.cols = std::max(1, static_cast<int>(std::ceil(bw / s)));
  l.rows = std::max(1, static_cast<int>(std::ceil(bh / s)));
  // centre the lattice on the bounding box
  l.x0 = box.min_corner().x() + 0.5 * (bw - (l.cols - 1) * s);
  l.y0 = box.min_corner().y() + 0.5 * (bh - (l.rows - 1) * s);
  return l;
}

/// Marks samples inside `free` with 0 and the others with -1 (even-odd scanline over all rings).
std::vector<int> fill_free(const MultiPolygon& free, const Lattice& l) {
  std::vector<int> scans(static_cast<std::size_t>(l.cols) * static_cast<std::size_t>(l.rows), -1);
  std::vector<std::vector<double>> xs(static_cast<std::size_t>(l.rows));
  auto add_ring = [&](const auto& ring) {
    const std::size_t n = ring.size();
    if (n < 3) return;
    // closed rings repeat the first vertex; an open ring gets its closing edge
    const bool closed = bg::equals(ring.front(), ring.back());
    const std::size_t edges = closed ? n - 1 : n;
    for (std::size_t k = 0; k < edges; ++k) {
      const Point& p = ring[k];
      const Point& q = ring[(k + 1) % n];
      const double ylo = std::min(p.y(), q.y()), yhi = std::max(p.y(), q.y());
      if (yhi == ylo) continue;
      // rows whose centre y satisfies ylo <= y < yhi
      int r0 = static_cast<int>(std::ceil((ylo - l.y0) / l.s));
      int r1 = static_cast<int>(std::ceil((yhi - l.y0) / l.s)) - 1;
      r0 = std::max(r0, 0);
      r1 = std::min(r1, l.rows - 1);
      for (int r = r0; r <= r1; ++r) {
        const double y = l.y0 + r * l.s;
        const double t = (y - p.y()) / (q.y() - p.y());
        xs[static_cast<std::size_t>(r)].push_back(p.x() + t * (q.x() - p.x()));
      }
    }
  };
  for (const auto& poly : free) {
    add_ring(poly.outer());
    for (const auto& in : poly.inners()) add_ring(in);
  }
  for (int r = 0; r < l.rows; ++r) {
    auto& row = xs[static_cast<std::size_t>(r)];
    std::sort(row.begin(), row.end());
    for (std::size_t k = 0; k + 1 < row.size(); k += 2) {
      const int c0 = std::max(0, static_cast<int>(std::ceil((row[k] - l.x0) / l.s)));
      const int c1 = std::min(l.cols - 1, static_cast<int>(std::ceil((row[k + 1] - l.x0) / l.s)) - 1);
      int* base = scans.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(l.cols);
      for (int c = c0; c <= c1; ++c) base[c] = 0;
    }
  }
  return scans;
}

/// Calls f(row, c0, c1) for the samples whose centres lie in the convex polygon ring[0..n) (one scanline per
/// lattice row: the span between the edges it crosses).
template <typename F>
void rasterise_convex(const Lattice& l, const Point* ring, std::size_t n, F&& f) {
  double ymin = ring[0].y(), ymax = ring[0].y();
  for (std::size_t k = 0; k < n; ++k) ymin = std::min(ymin, ring[k].y()), ymax = std::max(ymax, ring[k].y());
  const int r0 = std::max(0, static_cast<int>(std::ceil((ymin - l.y0) / l.s)));
  const int r1 = std::min(l.rows - 1, static_cast<int>(std::floor((ymax - l.y0) / l.s)));
  for (int r = r0; r <= r1; ++r) {
    const double y = l.y0 + r * l.s;
    double xmin = 1e300, xmax = -1e300;
    for (std::size_t k = 0; k < n; ++k) {
      const Point& p = ring[k];
      const Point& q = ring[(k + 1) % n];
      const double ylo = std::min(p.y(), q.y()), yhi = std::max(p.y(), q.y());
      if (y < ylo || y > yhi) continue;
      if (yhi - ylo < 1e-12) {
        xmin = std::min({xmin, p.x(), q.x()});
        xmax = std::max({xmax, p.x(), q.x()});
      } else {
        const double x = p.x() + (y - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
        xmin = std::min(xmin, x);
        xmax = std::max(xmax, x);
      }
    }
    if (xmin > xmax) continue;
    const int c0 = std::max(0, static_cast<int>(std::ceil((xmin - l.x0) / l.s)));
    const int c1 = std::min(l.cols - 1, static_cast<int>(std::floor((xmax - l.x0) / l.s)));
    if (c0 <= c1) f(r, c0, c1);
  }
}

/// Calls f(row, c0, c1) for the samples whose centres lie in the rectangle swept by a square of
/// width w along a-b, extended by ext_a before a and ext_b beyond b (w/2 each for a whole leg).
template <typename F>
void rasterise_leg(const Lattice& l, Point a, Point b, double w, F&& f, double ext_a, double ext_b) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double len = std::hypot(dx, dy);
  if (!(len > 1e-9) || !(w > 0.0)) return;
  const double ux = dx / len, uy = dy / len;  // along
  const double nx = -uy, ny = ux;             // normal
  const double h = 0.5 * w;
  const std::array<Point, 4> c = {
      Point{a.x() - ux * ext_a + nx * h, a.y() - uy * ext_a + ny * h},
      Point{b.x() + ux * ext_b + nx * h, b.y() + uy * ext_b + ny * h},
      Point{b.x() + ux * ext_b - nx * h, b.y() + uy * ext_b - ny * h},
      Point{a.x() - ux * ext_a - nx * h, a.y() - uy * ext_a - ny * h},
  };
  rasterise_convex(l, c.data(), c.size(), f);
}

/// Calls f(row, c0, c1) for the samples whose centres lie in the convex hull of `pts`.
template <typename F>
void rasterise_hull(const Lattice& l, const std::vector<Point>& pts, F&& f) {
  bg::model::multi_point<Point> mp(pts.begin(), pts.end());
  Polygon hull;
  bg::convex_hull(mp, hull);
  const auto& ring = hull.outer();  // closed: the last point repeats the first
  if (ring.size() < 4) return;
  rasterise_convex(l, ring.data(), ring.size() - 1, f);
}

/// A coverage part flown with a tilted gimbal (docs/patterns.md "Obliques"), with a footprint on the ground.
bool tilted(const PathPart& part, const CoverageOptions& o) {
  return part.kind == PartKind::Coverage && part.attitude.gimbal_pitch_deg &&
         *part.attitude.gimbal_pitch_deg > -90.0 + 1e-9 && o.hfov_deg > 0.0 && o.vfov_deg > 0.0;
}

double bearing_deg(Point a, Point b) {
  double d = std::atan2(b.x() - a.x(), b.y() - a.y()) * 180.0 / 3.14159265358979323846;
  return d < 0 ? d + 360.0 : d;
}

double polyline_length(const std::vector<Point>& pts) {
  double len = 0.0;
  for (std::size_t k = 1; k < pts.size(); ++k) len += bg::distance(pts[k - 1], pts[k]);
  return len;
}

template <typename Count>
void fill_stats(CoverageStats& st, const std::vector<Count>& counts, const std::vector<int>& free_mask,
                std::size_t n_free) {
  std::vector<std::size_t> hist(1, 0);
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (free_mask[i] < 0) continue;
    const auto k = static_cast<std::size_t>(counts[i]);
    if (k >= hist.size()) hist.resize(k + 1, 0);
    ++hist[k];
  }
  st.max_scans = static_cast<int>(hist.size()) - 1;
  while (st.max_scans > 0 && hist[static_cast<std::size_t>(st.max_scans)] == 0) --st.max_scans;
  hist.resize(static_cast<std::size_t>(st.max_scans) + 1);
  st.histogram.assign(hist.size(), 0.0);
  std::size_t once = 0, twice = 0;
  for (std::size_t k = 0; k < hist.size(); ++k) {
    if (n_free > 0) st.histogram[k] = static_cast<double>(hist[k]) / static_cast<double>(n_free);
    if (k >= 1) once += hist[k];
    if (k >= 2) twice += hist[k];
  }
  st.poc = n_free ? static_cast<double>(once) / static_cast<double>(n_free) : 0.0;
  st.pooc = n_free ? static_cast<double>(twice) / static_cast<double>(n_free) : 0.0;
}

void finish_rates(CoverageStats& st) {
  st.turns_per_1000m2 = st.area_m2 > 0.0 ? st.turns * 1000.0 / st.area_m2 : 0.0;
  st.length_per_1000m2 = st.area_m2 > 0.0 ? st.length_m * 1000.0 / st.area_m2 : 0.0;
}

}  // namespace

CoverageResult evaluate_coverage(const MultiPolygon& free, const std::vector<Flight>& flights,
                                 const CoverageOptions& options) {
  if (!(options.footprint_m > 0.0) || !std::isfinite(options.footprint_m))
    throw InputError("footprint_m", "the coverage footprint must be a positive number of metres");
  if (!options.uav_footprint_m.empty() && options.uav_footprint_m.size() != flights.size())
    throw InputError("footprint_m", "one footprint per flight is needed");
  for (const double w : options.uav_footprint_m)
    if (!(w > 0.0) || !std::isfinite(w))
      throw InputError("footprint_m", "every UAV's coverage footprint must be a positive number of metres");
  if (options.lattice_m < 0.0 || !std::isfinite(options.lattice_m))
    throw InputError("lattice_m", "the lattice spacing must be >= 0 (0 = adaptive)");
  CoverageResult res;
  res.uavs.resize(flights.size());
  const double area = free.empty() ? 0.0 : std::abs(bg::area(free));
  res.total.area_m2 = area;

  // lengths and turns do not depend on the lattice
  for (std::size_t u = 0; u < flights.size(); ++u) {
    res.uavs[u].footprint_m =
        options.uav_footprint_m.empty() ? options.footprint_m : options.uav_footprint_m[u];
    auto& st = res.uavs[u].stats;
    for (const auto& part : flights[u]) {
      st.length_m += polyline_length(part.local);
      if (part.kind == PartKind::Coverage) st.turns += static_cast<int>(part.local.size());
    }
    res.total.length_m += st.length_m;
    res.total.turns += st.turns;
  }

  if (free.empty() || !(area > 0.0)) {
    finish_rates(res.total);
    for (auto& u : res.uavs) finish_rates(u.stats);
    return res;
  }

  bg::model::box<Point> box;
  bg::envelope(free, box);
  const Lattice l = make_lattice(box, area, options);
  res.lattice_m = l.s;
  res.lattice_cols = l.cols;
  res.lattice_rows = l.rows;
  res.lattice_origin = Point{l.x0, l.y0};
  res.scans = fill_free(free, l);
  const std::vector<int> mask = res.scans;  // -1 outside, 0 inside
  std::size_t n_free = 0;
  for (int v : mask) n_free += v >= 0 ? 1 : 0;
  res.samples = n_free;

  const std::size_t n = res.scans.size();
  const std::size_t words = (n + 63) / 64;
  std::vector<std::vector<std::uint64_t>> touched(flights.size());
  std::vector<std::uint16_t> n_uavs(n, 0);
  std::vector<std::int32_t> mine(n, 0);
  auto check = [&options] {
    if (options.context != nullptr) options.context->check();
  };
  check();
  // oblique parts (docs/patterns.md "Obliques"): the samples each direction and the nadir parts see
  bool any_tilted = false;
  for (const auto& f : flights)
    for (const auto& part : f) any_tilted = any_tilted || tilted(part, options);
  std::vector<std::vector<std::uint64_t>> dir_bits;
  std::vector<std::uint64_t> nadir_bits(any_tilted ? words : 0, 0);
  for (std::size_t u = 0; u < flights.size(); ++u) {
    std::fill(mine.begin(), mine.end(), 0);
    for (const auto& part : flights[u]) {
      if (part.kind == PartKind::Transit && !options.count_transit) continue;
      std::uint64_t* seen = nullptr;  // the direction's (or the nadir parts') samples
      std::optional<photo::ObliqueFootprint> fp;
      if (any_tilted && part.kind == PartKind::Coverage) {
        if (tilted(part, options)) {
          const double pitch = *part.attitude.gimbal_pitch_deg;
          const double h = part.attitude.altitude_m.value_or(options.altitude_m);
          // a footprint that reaches the horizon (a facade orbit's camera) sees no bounded ground
          if (!(h > 0.0) || 90.0 + pitch + 0.5 * options.vfov_deg >= 89.0) continue;
          fp = photo::oblique_footprint(h, pitch, options.hfov_deg, options.vfov_deg);
          const double heading =
              part.attitude.heading_deg.empty()
                  ? (part.local.size() >= 2 ? bearing_deg(part.local[0], part.local[1]) : 0.0)
                  : part.attitude.heading_deg.front();
          std::size_t g = 0;
          auto apart = [](double x, double y) {  // degrees between two bearings
            const double d = std::fmod(std::abs(x - y), 360.0);
            return std::min(d, 360.0 - d);
          };
          while (g < res.oblique.size() && (apart(res.oblique[g].heading_deg, heading) > 0.05 ||
                                            std::abs(res.oblique[g].gimbal_pitch_deg - pitch) > 0.05))
            ++g;
          if (g == res.oblique.size()) {
            res.oblique.push_back({heading, pitch, 0.0, 0});
            dir_bits.emplace_back(words, 0);
          }
          ++res.oblique[g].parts;
          seen = dir_bits[g].data();
        } else {
          seen = nadir_bits.data();
        }
      }
      const auto count = [&](int r, int c0, int c1) {
        const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(l.cols);
        std::int32_t* base = mine.data() + row;
        for (int c = c0; c <= c1; ++c) ++base[c];
        if (seen != nullptr)
          for (int c = c0; c <= c1; ++c) {
            const std::size_t i = row + static_cast<std::size_t>(c);
            seen[i / 64] |= std::uint64_t{1} << (i % 64);
          }
      };
      for (std::size_t k = 1; k < part.local.size(); ++k) {
        if (k % 64 == 0) check();
        // turns and turnarounds with the camera off see nothing (docs/patterns.md)
        if (part.kind == PartKind::Coverage && !part.camera_on(k - 1)) continue;
        const Point a = part.local[k - 1], b = part.local[k];
        if (fp) {  // the trapezoid swept from a to b: the hull of its two positions (flat ground)
          const double heading = part.attitude.heading_deg.size() == part.local.size()
                                     ? part.attitude.heading_deg[k - 1]
                                 : part.attitude.heading_deg.empty() ? bearing_deg(a, b)
                                                                     : part.attitude.heading_deg.front();
          const auto ca = photo::footprint_corners(*fp, a, heading);
          const auto cb = photo::footprint_corners(*fp, b, heading);
          std::vector<Point> pts(ca.begin(), ca.end());
          pts.insert(pts.end(), cb.begin(), cb.end());
          rasterise_hull(l, pts, count);
          continue;
        }
        if (!options.widths) {
          const double w = res.uavs[u].footprint_m;
          rasterise_leg(l, a, b, w, count, 0.5 * w, 0.5 * w);
          continue;
        }
        // footprints that change along the leg (terrain): abutting pieces, each as wide as its middle's
        const double len = std::hypot(b.x() - a.x(), b.y() - a.y());
        const auto pieces = static_cast<std::size_t>(
            std::clamp(std::ceil(len / std::max(options.piece_m, 0.1)), 1.0, 10'000.0));
        const std::vector<double> w = options.widths(u, part.kind, a, b, pieces);
        for (std::size_t i = 0; i < pieces && i < w.size(); ++i) {
          const double t0 = static_cast<double>(i) / static_cast<double>(pieces);
          const double t1 = static_cast<double>(i + 1) / static_cast<double>(pieces);
          const Point p0{a.x() + t0 * (b.x() - a.x()), a.y() + t0 * (b.y() - a.y())};
          const Point p1{a.x() + t1 * (b.x() - a.x()), a.y() + t1 * (b.y() - a.y())};
          rasterise_leg(l, p0, p1, w[i], count, i == 0 ? 0.5 * w[i] : 0.0,
                        i + 1 == pieces ? 0.5 * w[i] : 0.0);
        }
      }
    }
    check();
    if (options.context != nullptr)
      options.context->report("evaluation", static_cast<double>(u + 1) / static_cast<double>(flights.size()));
    auto& bits = touched[u];
    bits.assign(words, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (mask[i] < 0 || mine[i] == 0) continue;
      res.scans[i] += mine[i];
      ++n_uavs[i];
      bits[i / 64] |= std::uint64_t{1} << (i % 64);
    }
    fill_stats(res.uavs[u].stats, mine, mask, n_free);
  }
  fill_stats(res.total, res.scans, mask, n_free);
  if (any_tilted) {
    auto share = [&](const std::vector<std::uint64_t>& bits) {
      std::size_t seen = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (mask[i] >= 0 && ((bits[i / 64] >> (i % 64)) & 1U)) ++seen;
      return n_free ? static_cast<double>(seen) / static_cast<double>(n_free) : 0.0;
    };
    res.nadir_poc = share(nadir_bits);
    for (std::size_t g = 0; g < res.oblique.size(); ++g) res.oblique[g].poc = share(dir_bits[g]);
  }

  // area share: every scanned sample split equally among the UAVs that scan it
  std::size_t covered = 0;
  for (std::size_t i = 0; i < n; ++i) covered += (mask[i] >= 0 && n_uavs[i] > 0) ? 1 : 0;
  for (std::size_t u = 0; u < flights.size(); ++u) {
    double share = 0.0;
    const auto& bits = touched[u];
    for (std::size_t wi = 0; wi < words; ++wi) {
      std::uint64_t b = bits[wi];
      while (b) {
        const int bit = __builtin_ctzll(b);
        b &= b - 1;
        share += 1.0 / n_uavs[wi * 64 + static_cast<std::size_t>(bit)];
      }
    }
    auto& uc = res.uavs[u];
    uc.area_share = covered ? share / static_cast<double>(covered) : 0.0;
    uc.stats.area_m2 = uc.area_share * area;
    finish_rates(uc.stats);
  }
  finish_rates(res.total);
  return res;
}

}  // namespace uavcover::evaluation
