// Refly the gaps (issue 32, docs/refly.md).
#include "usecases/refly.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <boost/geometry.hpp>
#include <charconv>
#include <cmath>
#include <map>
#include <set>

#include "engine/local_mission.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "uavcover/error.hpp"

namespace uavcover::usecases {

namespace bg = boost::geometry;

namespace {

/// The unscanned samples (0 scans) of the lattice as rectangles: runs along each row, a run that repeats
/// on the next row grown into one taller rectangle, then united.
MultiPolygon unscanned_cells(const evaluation::CoverageResult& c, const Context& ctx) {
  const double h = c.lattice_m / 2.0;
  MultiPolygon cells;
  std::map<std::pair<int, int>, int> open;  // (c0, c1) -> first row
  auto close = [&](int c0, int c1, int r0, int r1) {
    cells.push_back(geometry::box_polygon(
        c.lattice_origin.x() + c0 * c.lattice_m - h, c.lattice_origin.y() + r0 * c.lattice_m - h,
        c.lattice_origin.x() + c1 * c.lattice_m + h, c.lattice_origin.y() + r1 * c.lattice_m + h));
  };
  for (int r = 0; r <= c.lattice_rows; ++r) {
    if (r % 256 == 0 && ctx.stop_requested()) throw Cancelled();
    std::map<std::pair<int, int>, int> next;
    if (r < c.lattice_rows) {
      const int* row =
          c.scans.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(c.lattice_cols);
      for (int col = 0; col < c.lattice_cols;) {
        if (row[col] != 0) {
          ++col;
          continue;
        }
        int end = col;
        while (end + 1 < c.lattice_cols && row[end + 1] == 0) ++end;
        const auto key = std::make_pair(col, end);
        const auto it = open.find(key);
        next[key] = it == open.end() ? r : it->second;
        col = end + 1;
      }
    }
    for (const auto& [key, r0] : open)
      if (!next.contains(key)) close(key.first, key.second, r0, r - 1);
    open = std::move(next);
  }
  return geometry::unite(cells);
}

template <class Join>
MultiPolygon grown(const MultiPolygon& mp, double d, Join join) {
  if (mp.empty()) return {};
  MultiPolygon out;
  bg::buffer(mp, out, bg::strategy::buffer::distance_symmetric<double>(d),
             bg::strategy::buffer::side_straight(), join, bg::strategy::buffer::end_flat(),
             bg::strategy::buffer::point_circle(8));
  return out;
}

}  // namespace

nlohmann::json polygon_coordinates(const GeoPolygon& p) {
  nlohmann::json rings = nlohmann::json::array();
  for (const auto& ring : p) {
    nlohmann::json r = nlohmann::json::array();
    for (const auto& v : ring) r.push_back({v.lon, v.lat});
    rings.push_back(std::move(r));
  }
  return rings;
}

ReflyGaps lattice_gaps(const Plan& plan, const evaluation::CoverageResult& lattice, const Context& ctx) {
  ReflyGaps gaps;
  const double ds = plan.mission.spacing_m;
  const MultiPolygon cells = unscanned_cells(lattice, ctx);
  if (ctx.stop_requested()) throw Cancelled();
  // opening by an eighth of the spacing: slivers between swaths go, real gaps stay
  const double thin = std::max(ds / 8.0, lattice.lattice_m);
  const bg::strategy::buffer::join_miter miter;
  const MultiPolygon opened = grown(grown(cells, -thin, miter), thin, miter);
  const MultiPolygon reach = grown(opened, ds / 2.0, bg::strategy::buffer::join_round(16));
  const engine::LocalMission lm = engine::to_local(plan.mission);
  MultiPolygon clipped;
  bg::intersection(reach, lm.free, clipped);
  // pieces smaller than a sixteenth of a swath square are not worth a flight
  for (auto& poly : clipped) {
    if (bg::area(poly) < ds * ds / 16.0) continue;
    gaps.local.push_back(std::move(poly));
  }
  bg::correct(gaps.local);
  gaps.area_m2 = bg::area(gaps.local);
  gaps.area = engine::to_wgs84(gaps.local, lm.frame);
  return gaps;
}

ReflyGaps coverage_gaps(const Plan& plan, const std::vector<flight::Track>& tracks, const Context& ctx) {
  const flight::FlownCoverage flown = flight::flown_coverage(plan, tracks, ctx);
  ReflyGaps gaps = lattice_gaps(plan, flown.coverage, ctx);
  gaps.flown_poc = flown.flown_poc;
  gaps.planned_poc = flown.planned_poc;
  return gaps;
}

Mission refly_mission(const Plan& plan, const ReflyGaps& gaps, const std::vector<std::string>& uavs) {
  if (gaps.area.empty())
    throw InputError("area",
                     fmt::format("nothing is left to fly: the flight scanned {:.2f} % of the free area "
                                 "(the plan {:.2f} %) and no gap is wider than an eighth of the spacing",
                                 gaps.flown_poc * 100.0, gaps.planned_poc * 100.0));
  const Mission& m = plan.mission;
  std::set<std::string> wanted;
  for (const auto& id : uavs) {
    const bool known = std::any_of(m.uavs.begin(), m.uavs.end(), [&](const Uav& u) { return u.id == id; });
    if (!known) throw InputError("uavs", "'" + id.substr(0, 64) + "' is not a UAV of the plan");
    if (!wanted.insert(id).second) throw InputError("uavs", "'" + id + "' is given twice");
  }
  nlohmann::json j = strict::parse_json(mission_to_json(m, -1), "mission");
  j.erase("corridor");
  j.erase("structure");
  nlohmann::json polys = nlohmann::json::array();
  for (const auto& p : gaps.area) polys.push_back(polygon_coordinates(p));
  j["area"] = {{"type", "MultiPolygon"}, {"coordinates", std::move(polys)}};
  j["name"] = m.name + " (refly)";
  nlohmann::json kept = nlohmann::json::array();
  for (std::size_t i = 0; i < m.uavs.size(); ++i) {
    if (!wanted.empty() && !wanted.contains(m.uavs[i].id)) continue;
    nlohmann::json u = j["uavs"][i];
    u["start"] = {m.uavs[i].start_resolved.lon, m.uavs[i].start_resolved.lat};
    kept.push_back(std::move(u));
  }
  j["uavs"] = std::move(kept);
  return parse_mission(j.dump());
}

namespace {

double number_at(const nlohmann::json& v, const std::string& field) {
  if (!v.is_number()) throw InputError(field, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw InputError(field, "expected a finite number");
  return x;
}

std::vector<flight::Track> tracks_of_geojson(const nlohmann::json& fc, const std::string& field) {
  if (!fc.is_object() || fc.value("type", "") != "FeatureCollection" || !fc.contains("features") ||
      !fc["features"].is_array())
    throw InputError(field, "expected a GeoJSON FeatureCollection (a flight's log.geojson)");
  std::map<std::string, std::size_t> index;
  std::vector<flight::Track> out;
  const auto& features = fc["features"];
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& f = features[i];
    const std::string at = fmt::format("{}: features[{}]", field, i);
    if (!f.is_object() || !f.contains("properties") || !f["properties"].is_object()) continue;
    const auto& props = f["properties"];
    if (props.value("kind", "") != "track") continue;  // events are points; only tracks fly
    if (!props.contains("uav") || !props["uav"].is_string())
      throw InputError(at + ".properties.uav", "expected a string");
    if (!f.contains("geometry") || !f["geometry"].is_object() ||
        f["geometry"].value("type", "") != "LineString" || !f["geometry"].contains("coordinates") ||
        !f["geometry"]["coordinates"].is_array())
      throw InputError(at + ".geometry", "a track is a LineString");
    const std::string uav = props["uav"].get<std::string>();
    auto [it, fresh] = index.emplace(uav, out.size());
    if (fresh) out.push_back({uav, {}});
    auto& samples = out[it->second].second;
    const auto& coords = f["geometry"]["coordinates"];
    for (std::size_t k = 0; k < coords.size(); ++k) {
      const auto& c = coords[k];
      const std::string ck = fmt::format("{}.geometry.coordinates[{}]", at, k);
      if (!c.is_array() || c.size() < 2) throw InputError(ck, "expected [lon, lat, alt_m]");
      samples.push_back({number_at(c[0], ck), number_at(c[1], ck), c.size() > 2 ? number_at(c[2], ck) : 0.0});
    }
  }
  return out;
}

/// One CSV record's fields (RFC 4180 quotes; the log's data column is quoted JSON).
std::vector<std::string> csv_fields(std::string_view line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted) {
      if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        out.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      out.emplace_back();
    } else if (ch != '\r') {
      out.back() += ch;
    }
  }
  return out;
}

double csv_number(const std::string& s, const std::string& field) {
  double x = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(x))
    throw InputError(field, "expected a number, got '" + s.substr(0, 40) + "'");
  return x;
}

std::vector<flight::Track> tracks_of_csv(std::string_view text, const std::string& field) {
  std::vector<flight::Track> out;
  std::map<std::string, std::size_t> index;
  std::map<std::string, std::size_t> col;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const auto nl = text.find('\n');
    const std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++line_no;
    if (line.empty()) continue;
    const auto f = csv_fields(line);
    if (col.empty()) {
      for (std::size_t i = 0; i < f.size(); ++i) col[f[i]] = i;
      for (const char* need : {"uav", "kind", "lon", "lat", "alt_m"})
        if (!col.contains(need)) throw InputError(field, std::string("the CSV log has no column ") + need);
      continue;
    }
    const std::string at = fmt::format("{}: line {}", field, line_no);
    if (f.size() < col.size()) throw InputError(at, "fewer fields than the header");
    if (f[col["kind"]] != "telemetry" || f[col["lon"]].empty() || f[col["lat"]].empty()) continue;
    const std::string& uav = f[col["uav"]];
    auto [it, fresh] = index.emplace(uav, out.size());
    if (fresh) out.push_back({uav, {}});
    const std::string& alt = f[col["alt_m"]];
    out[it->second].second.push_back({csv_number(f[col["lon"]], at + " lon"),
                                      csv_number(f[col["lat"]], at + " lat"),
                                      alt.empty() ? 0.0 : csv_number(alt, at + " alt_m")});
  }
  if (col.empty()) throw InputError(field, "the log is empty");
  return out;
}

}  // namespace

std::vector<flight::Track> parse_flight_log(std::string_view text, const std::string& field) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && text[first] == '{')
    return tracks_of_geojson(strict::parse_json(text, field), field);
  return tracks_of_csv(text, field);
}

}  // namespace uavcover::usecases
