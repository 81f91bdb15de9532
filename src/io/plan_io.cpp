#include "io/plan_io.hpp"
#include "io/write_artifacts.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmath>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <system_error>

#include "engine/test_hold.hpp"
#include "geodesy/local_frame.hpp"
#include "geometry/geometry.hpp"
#include "json/strict.hpp"
#include "mission/mission_json.hpp"
#include "photo/photo.hpp"
#include "sorties/sorties.hpp"
#include "uavcover/error.hpp"
#include "uavcover/uavcover.hpp"

namespace uavcover::io {

using nlohmann::json;

namespace {

const char* kind_name(PartKind k) { return k == PartKind::Coverage ? "coverage" : "transit"; }

json line_coords(const std::vector<LonLat>& pts) {
  json c = json::array();
  for (const auto& p : pts) c.push_back({p.lon, p.lat});
  return c;
}

/// The transit parts before the first coverage part of a sortie (out) or after its last (back), as one
/// line of positions (empty when there are none).
json sortie_transit(const Sortie& s, bool out) {
  std::vector<LonLat> pts;
  auto add = [&](const PathPart& part) {
    for (const auto& p : part.wgs84)
      if (pts.empty() || pts.back().lon != p.lon || pts.back().lat != p.lat) pts.push_back(p);
  };
  if (out) {
    for (const auto& part : s.parts) {
      if (part.kind == PartKind::Coverage) break;
      add(part);
    }
  } else {
    std::size_t k = s.parts.size();
    while (k > 0 && s.parts[k - 1].kind != PartKind::Coverage) --k;
    for (; k < s.parts.size(); ++k) add(s.parts[k]);
  }
  return line_coords(pts);
}

json sorties_json(const UavPlan& u) {
  json out = json::array();
  for (const auto& s : u.sorties)
    out.push_back({{"index", s.index},
                   {"first_waypoint", s.first_waypoint},
                   {"last_waypoint", s.last_waypoint},
                   {"turns", s.turns},
                   {"length_m", s.length_m},
                   {"duration_min", s.duration_min},
                   {"transit_out", sortie_transit(s, true)},
                   {"transit_back", sortie_transit(s, false)}});
  return out;
}

json parse_file(const std::filesystem::path& p, const std::string& field) {
  return strict::parse_json(read_text_file(p, field), field);
}

std::atomic<std::size_t> g_max_input_bytes{0};  // 0: not set, use the environment or the default

std::string mib(std::size_t bytes) {
  return bytes % (std::size_t{1} << 20) == 0 ? std::to_string(bytes >> 20) + " MiB"
                                             : std::to_string(bytes) + " bytes";
}

// Why a file of this kind is not read ("" for a regular file).
std::string kind_problem(const struct stat& st, const std::string& name) {
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return name + " is a folder, not a file";
  return name + " is not a regular file (a device, a pipe or a socket); give a file";
}

}  // namespace

std::size_t max_input_bytes() {
  if (const std::size_t set = g_max_input_bytes.load()) return set;
  const char* env = std::getenv("UAVCOVER_MAX_INPUT_MB");
  if (env == nullptr || *env == '\0') return kDefaultMaxInputBytes;
  const std::string_view v(env);
  unsigned long mb = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), mb);
  if (ec != std::errc() || end != v.data() + v.size() || mb < 1 || mb > 4096)
    throw InputError("UAVCOVER_MAX_INPUT_MB",
                     "must be a whole number of MiB in 1..4096, got '" + std::string(v.substr(0, 40)) + "'");
  return static_cast<std::size_t>(mb) << 20;
}

void set_max_input_bytes(std::size_t bytes) { g_max_input_bytes.store(bytes); }

std::string read_text_file(const std::filesystem::path& path, const std::string& field) {
  return read_text_file(path, field, max_input_bytes());
}

std::string read_text_file(const std::filesystem::path& path, const std::string& field,
                           std::size_t max_bytes) {
  const std::string name = "'" + path.string() + "'";
  struct stat st {};
  // folders and devices are refused before they are opened (opening a pipe or a device can block)
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(field, "cannot read file " + name + ": " + std::strerror(errno));
  if (const std::string why = kind_problem(st, name); !why.empty()) throw InputError(field, why);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(field, "cannot read file " + name + ": " + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &st) != 0) throw OperationError("cannot read file " + name + ": " + std::strerror(errno));
  // what was opened may differ from what was checked (the path was replaced in between)
  if (const std::string why = kind_problem(st, name); !why.empty()) throw InputError(field, why);
  auto too_large = [&] {
    return InputError(
        field, name + " is larger than the input limit of " + mib(max_bytes) + " (see docs/limits.md)");
  };
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large();
  // read at most max_bytes + 1 bytes, whatever the size said (files that grow, /proc files)
  std::string text(std::min<std::size_t>(static_cast<std::size_t>(st.st_size), max_bytes) + 1, '\0');
  std::size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (got > max_bytes) throw too_large();
      text.resize(std::min(max_bytes + 1, std::max<std::size_t>(got * 2, 4096)));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw OperationError("cannot read file " + name + ": " + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) throw too_large();
  text.resize(got);
  return text;
}

json paths_geojson(const Plan& plan, std::optional<std::size_t> only_uav) {
  json features = json::array();
  for (std::size_t a = 0; a < plan.mission.area.size(); ++a)
    features.push_back({{"type", "Feature"},
                        {"properties", {{"role", "area"}, {"index", a}}},
                        {"geometry", mission::geo_polygon_json(plan.mission.area[a])}});
  for (std::size_t z = 0; z < plan.mission.no_fly_zones.size(); ++z)
    features.push_back({{"type", "Feature"},
                        {"properties", {{"role", "no_fly_zone"}, {"index", z}}},
                        {"geometry", mission::geo_polygon_json(plan.mission.no_fly_zones[z])}});
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    if (only_uav && *only_uav != i) continue;
    const auto& u = plan.uavs[i];
    int part_index = 0;
    for (const auto& part : u.parts) {
      const double len = geometry::length(part.local);
      const int turns = part.kind == PartKind::Coverage ? static_cast<int>(part.local.size()) : 0;
      // the segments flown with the camera off (turns, turnarounds: docs/patterns.md), by index
      json off = json::array();
      for (std::size_t k = 0; k < part.camera_off.size(); ++k)
        if (part.camera_off[k] != 0) off.push_back(k);
      features.push_back({{"type", "Feature"},
                          {"properties",
                           {{"uav", u.id},
                            {"kind", kind_name(part.kind)},
                            {"part", part_index++},
                            {"share_requested", u.share_requested},
                            {"share_actual", u.share_actual},
                            {"length_m", len},
                            {"turns", turns}}},
                          {"geometry", {{"type", "LineString"}, {"coordinates", line_coords(part.wgs84)}}}});
      if (!off.empty()) features.back()["properties"]["camera_off"] = std::move(off);
    }
  }
  return {{"type", "FeatureCollection"}, {"features", std::move(features)}};
}

json plan_json(const Plan& plan, const json& extra) {
  const Mission& m = plan.mission;
  json uavs = json::array();
  double total_len = 0, total_cov = 0;
  int total_turns = 0;
  for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
    const auto& u = plan.uavs[i];
    const auto& mu = m.uavs.at(i);
    json region = json::array();
    for (const auto& poly : u.region) region.push_back(mission::geo_polygon_json(poly).at("coordinates"));
    uavs.push_back({{"id", u.id},
                    {"start", {mu.start_resolved.lon, mu.start_resolved.lat}},
                    {"start_given", mu.start.has_value()},
                    {"share_requested", u.share_requested},
                    {"share_actual", u.share_actual},
                    {"regions", u.regions},
                    {"region", {{"type", "MultiPolygon"}, {"coordinates", std::move(region)}}},
                    {"coverage_length_m", u.coverage_length_m},
                    {"length_m", u.length_m},
                    {"turns", u.turns},
                    {"transition_altitude_m", u.transition_altitude_m},
                    {"batteries", u.sorties.size()},
                    {"sorties", sorties_json(u)},
                    {"diagnostics", u.diagnostics}});
    total_len += u.length_m;
    total_cov += u.coverage_length_m;
    total_turns += u.turns;
  }
  json j = {
      {"uavcover_version", "0.1.0"},
      {"mission", mission::to_json(m)},
      {"origin", {plan.origin.lon, plan.origin.lat}},
      {"spacing_m", m.spacing_m},
      {"gsd_m", m.gsd_m ? json(*m.gsd_m) : json(nullptr)},
      {"footprint_m", m.footprint_m ? json(*m.footprint_m) : json(nullptr)},
      {"altitude_m", m.altitude_m},
      {"altitude_source", m.altitude_source},
      {"mode", m.mode == Mode::Strict ? "strict" : "coverage"},
      {"seed", m.seed},
      {"battery_reserve", m.battery_reserve},
      {"planner", plan.planner},
      {"complete", plan.complete},
      {"planner_diagnostics", plan.diagnostics},
      {"warnings", plan.warnings},
      {"uavs", std::move(uavs)},
      {"totals",
       {{"length_m", total_len},
        {"coverage_length_m", total_cov},
        {"turns", total_turns},
        {"free_area_m2", plan.free_area_m2},
        {"compute_time_s", plan.compute_time_s}}},
  };
  if (const auto images = photo::estimate(plan)) j["images"] = photo::to_json(*images);
  for (auto it = extra.begin(); it != extra.end(); ++it) j[it.key()] = it.value();
  return j;
}

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  std::error_code mkdir_ec;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), mkdir_ec);
  if (mkdir_ec) throw OperationError("cannot create the folder " + path.parent_path().string());
  const std::filesystem::path tmp = path.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw OperationError("cannot write " + tmp.string());
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw OperationError("cannot write " + tmp.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw OperationError("cannot write " + path.string());
  }
}

namespace {

std::filesystem::path checked_relative(const std::string& name) {
  const std::filesystem::path rel(name);
  bool ok = !name.empty() && rel.is_relative() && name.find('\\') == std::string::npos;
  for (const auto& part : rel) ok = ok && !part.empty() && part != "." && part != "..";
  if (!ok) throw OperationError("refusing to write an output named \"" + name + "\"");
  return rel;
}

}  // namespace

namespace {

std::vector<std::filesystem::path> write_staged(const std::filesystem::path& dir_in,
                                                const Artifacts& artifacts, const Context* ctx) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path dir = dir_in.lexically_normal();
  if (!dir.has_filename() && dir.has_relative_path()) dir = dir.parent_path();  // "a/b/" -> "a/b"
  if (dir.empty()) dir = ".";
  const bool fresh = !fs::exists(dir, ec);
  if (fresh) {
    if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
    if (ec) throw OperationError("cannot create the folder " + dir.parent_path().string());
  } else if (!fs::is_directory(dir, ec)) {
    throw OperationError("cannot create the folder " + dir.string());
  }
  const std::string tag = ".staging-" + std::to_string(::getpid());
  // a fresh folder is staged beside itself and renamed into place whole; an existing one inside
  const fs::path staging = fresh ? dir.parent_path() / ("." + dir.filename().string() + tag) : dir / tag;
  fs::remove_all(staging, ec);
  auto stopped = [ctx] { return ctx != nullptr && ctx->stop_requested(); };
  std::vector<fs::path> written;
  try {
    fs::create_directories(staging);
    for (const auto& a : artifacts) {
      if (stopped()) throw Cancelled();
      const fs::path rel = checked_relative(a.name);
      const fs::path tmp = staging / rel;
      fs::create_directories(tmp.parent_path());
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out.write(a.bytes.data(), static_cast<std::streamsize>(a.bytes.size()));
      out.flush();
      if (!out) throw OperationError("cannot write " + (dir / rel).string());
    }
    if (ctx != nullptr) engine::test_hold(*ctx, "storing", "");
    if (stopped()) throw Cancelled();
    // past this point the outputs are committed: a stop no longer undoes them
    if (fresh) {
      fs::rename(staging, dir);
      for (const auto& a : artifacts) written.push_back(dir / checked_relative(a.name));
      return written;
    }
    for (const auto& a : artifacts) {
      const fs::path rel = checked_relative(a.name);
      fs::create_directories((dir / rel).parent_path());
      fs::rename(staging / rel, dir / rel);
      written.push_back(dir / rel);
    }
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(staging, ec);
    throw OperationError(std::string("cannot write the outputs: ") + e.what());
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  fs::remove_all(staging, ec);
  return written;
}

}  // namespace

std::vector<std::filesystem::path> write_artifacts(const std::filesystem::path& dir,
                                                   const Artifacts& artifacts) {
  return write_staged(dir, artifacts, nullptr);
}

std::vector<std::filesystem::path> write_artifacts(const std::filesystem::path& dir,
                                                   const Artifacts& artifacts, const Context& ctx) {
  return write_staged(dir, artifacts, &ctx);
}

namespace {

/// A WGS84 position from a GeoJSON coordinate array, checked.
LonLat position(const json& c, const std::string& field) {
  if (!c.is_array() || c.size() < 2 || !c[0].is_number() || !c[1].is_number())
    throw InputError(field, "expected [longitude, latitude]");
  const LonLat ll{c[0].get<double>(), c[1].get<double>()};
  if (!std::isfinite(ll.lon) || !std::isfinite(ll.lat) || std::fabs(ll.lon) > 180.0 ||
      std::fabs(ll.lat) > 90.0)
    throw InputError(field, "not a WGS84 position");
  return ll;
}

/// Positions of a plan must lie near the mission: within this distance of the frame's origin.
constexpr double kMaxPlanExtentM = 500'000.0;

int whole(const json& j, const std::string& field, int lo, int hi) {
  if (!j.is_number_integer()) throw InputError(field, "expected a whole number");
  const auto v = j.get<std::int64_t>();
  if (v < lo || v > hi)
    throw InputError(field, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(v);
}

}  // namespace

Plan load_plan_dir(const std::filesystem::path& dir) {
  const auto plan_path = dir / "plan.json";
  const auto paths_path = dir / "paths.geojson";
  if (!std::filesystem::is_directory(dir))
    throw InputError("PLAN_DIR",
                     "no plan folder at " + dir.string() + " (expected plan.json and paths.geojson)");
  if (!std::filesystem::exists(plan_path)) throw InputError("PLAN_DIR", "no plan.json in " + dir.string());
  if (!std::filesystem::exists(paths_path))
    throw InputError("PLAN_DIR", "no paths.geojson in " + dir.string());
  return load_plan(parse_file(plan_path, "plan.json"), parse_file(paths_path, "paths.geojson"));
}

Plan load_plan(const json& pj, const json& gj) {
  Plan plan;
  try {
    if (!pj.is_object() || !pj.contains("mission")) throw InputError("plan.json: mission", "missing");
    plan.mission = parse_mission(pj["mission"].dump(), ParseOptions{std::size_t{1} << 40});
    plan.origin = position(pj.at("origin"), "plan.json: origin");
    const geodesy::LocalFrame frame(plan.origin);
    if (const Point c = frame.to_local(geodesy::centroid(plan.mission.area));
        !(std::hypot(c.x(), c.y()) <= kMaxPlanExtentM))
      throw InputError("plan.json: origin", "lies more than 500 km from the mission's area");
    auto local = [&](const LonLat& ll, const std::string& field) {
      const Point p = frame.to_local(ll);
      if (!(std::hypot(p.x(), p.y()) <= kMaxPlanExtentM))
        throw InputError(field, "lies more than 500 km from the mission");
      return p;
    };
    const auto& ju = pj.at("uavs");
    if (!ju.is_array() || ju.size() != plan.mission.uavs.size())
      throw InputError("plan.json: uavs", "does not match the mission's UAVs");
    plan.planner = pj.at("planner").get<std::string>();
    plan.complete = pj.at("complete").get<bool>();
    plan.diagnostics = pj.at("planner_diagnostics");
    plan.warnings = pj.at("warnings").get<std::vector<std::string>>();
    plan.free_area_m2 = pj.at("totals").at("free_area_m2").get<double>();
    plan.compute_time_s = pj.at("totals").at("compute_time_s").get<double>();
    // sorties (docs/sorties.md): read here, checked and completed once the paths are read
    std::vector<std::vector<Sortie>> sorties(ju.size());
    bool any_sorties = false;
    for (std::size_t i = 0; i < ju.size(); ++i) {
      if (!ju[i].is_object() || !ju[i].contains("sorties")) continue;
      any_sorties = true;
      const std::string f = "plan.json: uavs[" + std::to_string(i) + "].sorties";
      const json& js = ju[i]["sorties"];
      if (!js.is_array()) throw InputError(f, "expected an array");
      for (std::size_t k = 0; k < js.size(); ++k) {
        const std::string fk = f + "[" + std::to_string(k) + "]";
        const json& e = js[k];
        if (!e.is_object()) throw InputError(fk, "expected an object");
        Sortie s;
        s.index = whole(e.at("index"), fk + ".index", 0, 1 << 30);
        s.first_waypoint = whole(e.at("first_waypoint"), fk + ".first_waypoint", 0, 1 << 30);
        s.last_waypoint = whole(e.at("last_waypoint"), fk + ".last_waypoint", 0, 1 << 30);
        for (const char* name : {"transit_out", "transit_back"}) {
          const json& line = e.at(name);
          if (!line.is_array() || line.size() == 1)
            throw InputError(fk + "." + name, "expected an empty array or at least 2 positions");
          PathPart t{PartKind::Transit, {}, {}};
          for (const auto& c : line) {
            t.wgs84.push_back(position(c, fk + "." + name));
            t.local.push_back(local(t.wgs84.back(), fk + "." + name));
          }
          s.parts.push_back(std::move(t));
        }
        sorties[i].push_back(std::move(s));
      }
    }
    if (any_sorties && pj.contains("battery_reserve")) {
      const json& r = pj["battery_reserve"];
      if (!r.is_number() || !(r.get<double>() >= 0.0 && r.get<double>() <= 0.9))
        throw InputError("plan.json: battery_reserve", "must be a number in [0, 0.9]");
    }
    for (std::size_t i = 0; i < ju.size(); ++i) {
      const std::string f = "plan.json: uavs[" + std::to_string(i) + "]";
      auto& mu = plan.mission.uavs[i];
      mu.start_resolved = position(ju[i].at("start"), f + ".start");
      (void)local(mu.start_resolved, f + ".start");
      UavPlan up;
      up.id = ju[i].at("id").get<std::string>();
      if (up.id != mu.id) throw InputError(f + ".id", "does not match the mission's UAV \"" + mu.id + "\"");
      up.share_requested = ju[i].at("share_requested").get<double>();
      up.share_actual = ju[i].at("share_actual").get<double>();
      up.regions = ju[i].at("regions").get<int>();
      up.coverage_length_m = ju[i].at("coverage_length_m").get<double>();
      up.length_m = ju[i].at("length_m").get<double>();
      up.turns = ju[i].at("turns").get<int>();
      up.transition_altitude_m = ju[i].at("transition_altitude_m").get<double>();
      up.diagnostics = ju[i].at("diagnostics");
      const auto& region = ju[i].at("region");
      if (!region.is_object() || region.value("type", "") != "MultiPolygon" ||
          !region.at("coordinates").is_array())
        throw InputError(f + ".region", "expected a GeoJSON MultiPolygon");
      for (const auto& jpoly : region.at("coordinates")) {
        GeoPolygon gp;
        Polygon lp;
        for (const auto& jring : jpoly) {
          if (!jring.is_array() || jring.size() < 4)
            throw InputError(f + ".region", "rings need 4 positions");
          GeoRing ring;
          Polygon::ring_type lring;
          for (const auto& c : jring) {
            ring.push_back(position(c, f + ".region"));
            lring.push_back(local(ring.back(), f + ".region"));
          }
          (gp.empty() ? lp.outer() : (lp.inners().push_back({}), lp.inners().back())) = std::move(lring);
          gp.push_back(std::move(ring));
        }
        if (gp.empty()) throw InputError(f + ".region", "empty polygon");
        bg::correct(lp);
        if (std::string why; !bg::is_valid(lp, why))
          throw InputError(f + ".region", "not a valid polygon: " + why);
        up.region.push_back(std::move(gp));
        up.region_local.push_back(std::move(lp));
      }
      plan.uavs.push_back(std::move(up));
    }
    if (!gj.is_object() || !gj.contains("features") || !gj["features"].is_array())
      throw InputError("paths.geojson: features", "missing");
    std::size_t index = 0;
    for (const auto& feature : gj["features"]) {
      const std::string f = "paths.geojson: features[" + std::to_string(index++) + "]";
      const auto& props = feature.at("properties");
      if (!props.is_object() || !props.contains("uav")) continue;
      const std::string id = props.at("uav").get<std::string>();
      auto it =
          std::find_if(plan.uavs.begin(), plan.uavs.end(), [&](const UavPlan& u) { return u.id == id; });
      if (it == plan.uavs.end()) throw InputError(f + ".properties.uav", "unknown UAV \"" + id + "\"");
      const std::string kind = props.at("kind").get<std::string>();
      if (kind != "coverage" && kind != "transit")
        throw InputError(f + ".properties.kind",
                         "expected \"coverage\" or \"transit\", got \"" + kind + "\"");
      const auto& geometry = feature.at("geometry");
      if (geometry.value("type", "") != "LineString" || !geometry.at("coordinates").is_array() ||
          geometry.at("coordinates").size() < 2)
        throw InputError(f + ".geometry", "expected a LineString of at least 2 positions");
      PathPart part;
      part.kind = kind == "coverage" ? PartKind::Coverage : PartKind::Transit;
      for (const auto& c : geometry.at("coordinates")) {
        part.wgs84.push_back(position(c, f + ".geometry.coordinates"));
        part.local.push_back(local(part.wgs84.back(), f + ".geometry.coordinates"));
      }
      if (props.contains("camera_off")) {
        const auto& off = props.at("camera_off");
        if (!off.is_array())
          throw InputError(f + ".properties.camera_off", "expected an array of segment indices");
        part.camera_off.assign(part.local.size() - 1, 0);
        for (const auto& k : off) {
          if (!k.is_number_unsigned() || k.get<std::size_t>() >= part.camera_off.size())
            throw InputError(f + ".properties.camera_off",
                             "expected segment indices below " + std::to_string(part.camera_off.size()));
          part.camera_off[k.get<std::size_t>()] = 1;
        }
      }
      it->parts.push_back(std::move(part));
    }
    if (any_sorties) {
      for (std::size_t i = 0; i < plan.uavs.size(); ++i) {
        sorties::rebuild_sorties(plan, i, sorties[i], "plan.json: uavs[" + std::to_string(i) + "].sorties");
        plan.uavs[i].sorties = std::move(sorties[i]);
      }
    } else {
      // a plan folder from before sorties: cut them now (as plan() would)
      sorties::fill_sorties(plan, {}, &plan.warnings);
    }
  } catch (const json::exception& e) {
    throw InputError("PLAN_DIR",
                     std::string("plan.json or paths.geojson is not a uavcover plan: ") + e.what());
  }
  return plan;
}

}  // namespace uavcover::io
