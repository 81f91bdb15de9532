#include "export/formats.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "export/support.hpp"
#include "export/zip.hpp"
#include "render/render.hpp"
#include "uavcover/error.hpp"

namespace uavcover::exporting {

using nlohmann::json;

namespace {

void put(Artifacts& out, std::string name, std::string_view media_type, std::string bytes) {
  out.push_back({std::move(name), std::string(media_type), std::move(bytes)});
}

void write_geojson(const Plan& p, std::size_t i, const ExportOptions& /*opt*/, const std::string& base,
                   Artifacts& out) {
  const json doc = uav_geojson(p, i);
  const auto problems = validate_geojson(doc);
  if (!problems.empty())
    throw InputError(fmt::format("uavs[{}]", i), "its GeoJSON export is invalid: " + problems.front());
  put(out, base + ".geojson", "application/geo+json", dump(doc, 1));
}

void write_qgc(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
               Artifacts& out) {
  put(out, base + ".plan", "application/json", dump(qgc_plan(p, i, opt), 4));
}

void write_wpl(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
               Artifacts& out) {
  put(out, base + ".waypoints", "text/plain", wpl_text(p, i, opt));
}

void write_kml(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
               Artifacts& out) {
  std::string kml = kml_text(p, i, opt);
  if (opt.kmz) put(out, base + ".kmz", "application/vnd.google-earth.kmz", zip_bytes({{"doc.kml", kml}}));
  put(out, base + ".kml", "application/vnd.google-earth.kml+xml", std::move(kml));
}

void write_dji(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
               Artifacts& out) {
  put(out, base + ".wpml.kmz", "application/vnd.google-earth.kmz", zip_bytes(dji_wpml(p, i, opt)));
}

void write_litchi(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
                  Artifacts& out) {
  auto missions = litchi_csv(p, i, opt);
  if (missions.size() == 1) {
    put(out, base + ".litchi.csv", "text/csv", std::move(missions.front()));
  } else {
    for (std::size_t k = 0; k < missions.size(); ++k)
      put(out, fmt::format("{}.{}.litchi.csv", base, k + 1), "text/csv", std::move(missions[k]));
  }
}

void write_csv(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
               Artifacts& out) {
  put(out, base + ".csv", "text/csv", waypoints_csv(p, i, opt));
}

/// UAV `i`'s trajectory under the export's options: made once per export when the caller keeps them
/// (ExportOptions::trajectories), so the trajectory and its plot share it.
trajectory::Trajectory trajectory_of(const Plan& p, std::size_t i, const ExportOptions& opt) {
  if (opt.trajectories == nullptr) return trajectory::uav_trajectory(p, i, opt.trajectory, opt.altitude);
  auto it = opt.trajectories->find(p.uavs[i].id);
  if (it == opt.trajectories->end())
    it = opt.trajectories
             ->emplace(p.uavs[i].id, trajectory::uav_trajectory(p, i, opt.trajectory, opt.altitude))
             .first;
  return it->second;
}

void write_trajectory(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& /*base*/,
                      Artifacts& out) {
  const auto traj = trajectory_of(p, i, opt);
  // the segment form is the fillet-lines method's: a polynomial trajectory is sampled, at its own step
  // (trajectory::Options::dt) when none is given
  const bool segments = opt.trajectory_step_s <= 0 && traj.method() == trajectory::Method::FilletLines;
  const double step = opt.trajectory_step_s > 0 ? opt.trajectory_step_s : opt.trajectory.dt;
  put(out, "trajectory/" + p.uavs[i].id + ".csv", "text/csv",
      segments ? trajectory::segments_csv(p, traj) : trajectory::trajectory_csv(p, traj.sample(step)));
}

void write_trajectory_plot(const Plan& p, std::size_t i, const ExportOptions& opt, const std::string& base,
                           Artifacts& out) {
  const auto traj = trajectory_of(p, i, opt);
  out.push_back(render::trajectory_png(traj, base + ".trajectory.png", p.uavs[i].id + ": trajectory"));
}

}  // namespace

const std::vector<Format>& formats() {
  static const std::vector<Format> table{
      {"geojson", "GeoJSON (RFC 7946)", ".geojson", "application/geo+json", "GIS tools, the web app", false,
       "positions [lon, lat], closed counter-clockwise rings, clockwise holes", &write_geojson},
      {"qgc", "QGroundControl .plan", ".plan", "application/json", "QGroundControl, PX4, ArduPilot", true,
       "firmwareType from the autopilot; PX4 accepts the geofence; the autopilots' upload rules", &write_qgc},
      {"wpl", "Mission Planner QGC WPL 110", ".waypoints", "text/plain", "Mission Planner, ArduPilot", true,
       "speed at most 20 m/s (WPNAV_SPEED); ArduPilot's upload rules", &write_wpl},
      {"kml", "KML", ".kml", "application/vnd.google-earth.kml+xml", "Google Earth, GIS tools", true,
       "altitude mode relativeToGround, clampToGround or absolute", &write_kml},
      {"dji", "DJI WPML (.kmz)", ".wpml.kmz", "application/vnd.google-earth.kmz", "DJI Pilot 2, FlightHub 2",
       true, "speed at most 15 m/s, heights at most 500 m above take-off", &write_dji},
      {"litchi", "Litchi mission CSV", ".litchi.csv", "text/csv", "Litchi", true,
       "at most 99 waypoints per mission (split), speed 0..15 m/s, altitude -200..500 m", &write_litchi},
      {"csv", "Mission items CSV", ".csv", "text/csv", "spreadsheets, scripts", true,
       "seq,role,command,frame,lat,lon,alt_m,param1..param4", &write_csv},
      {"trajectory", "Trajectory CSV", ".csv", "text/csv", "analysis, simulators", false,
       "time-parameterised flight within the UAV's speed and acceleration limits: the segment form (one row "
       "per breakpoint), or sampled with a step; the polynomial method always sampled (docs/trajectory.md)",
       &write_trajectory, true},
      {"trajectory_plot", "Trajectory plot (PNG)", ".trajectory.png", "image/png", "people, reports", false,
       "position, velocity and acceleration against time, the limits dashed (docs/trajectory.md)",
       &write_trajectory_plot, true},
  };
  return table;
}

const Format* find_format(std::string_view name) {
  const auto& t = formats();
  const auto it = std::find_if(t.begin(), t.end(), [&](const Format& f) { return f.name == name; });
  return it == t.end() ? nullptr : &*it;
}

const std::vector<std::string>& known_formats() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Format& f : formats()) n.emplace_back(f.name);
    return n;
  }();
  return names;
}

std::string format_list() {
  std::string list;
  for (const auto& k : known_formats()) list += (list.empty() ? "" : ", ") + k;
  return list;
}

json formats_json() {
  json out = json::array();
  for (const Format& f : formats())
    out.push_back({{"name", f.name},
                   {"title", f.title},
                   {"extension", f.extension},
                   {"media_type", f.media_type},
                   {"consumers", f.consumers},
                   {"per_sortie", f.per_sortie},
                   {"limits", f.limits}});
  return out;
}

std::vector<std::string> parse_formats(const std::vector<std::string>& formats) {
  std::vector<std::string> wanted;
  for (const auto& entry : formats) {
    std::size_t pos = 0;
    while (pos <= entry.size()) {
      const std::size_t comma = std::min(entry.find(',', pos), entry.size());
      std::string f = entry.substr(pos, comma - pos);
      f.erase(0, f.find_first_not_of(" \t"));
      f.erase(f.find_last_not_of(" \t") + 1);
      for (auto& c : f) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      pos = comma + 1;
      if (f.empty()) continue;
      if (find_format(f) == nullptr)
        throw InputError("formats", "unknown format \"" + f + "\" (known: " + format_list() + ")");
      if (std::find(wanted.begin(), wanted.end(), f) == wanted.end()) wanted.push_back(f);
    }
  }
  if (wanted.empty()) throw InputError("formats", "no format given");
  return wanted;
}

}  // namespace uavcover::exporting
