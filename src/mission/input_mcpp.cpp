// The mCPP-optimized-DARP input format.
#include "mission/parse_internal.hpp"
#include "uavcover/error.hpp"

namespace uavcover::mission::detail {

// mCPP-optimized-DARP input (droneNo, scanningDensity, polygon [{lat,long}], obstacles,
// pathsStrictlyInPoly, initialPos, rPortions).
Raw parse_mcpp(const json& j) {
  Raw raw;
  raw.format = "mcpp-optimized-darp";
  raw.name = "imported mCPP-optimized-DARP mission";
  auto latlong_ring = [](const json& arr, const std::string& f) {
    if (!arr.is_array()) throw InputError(f, "expected an array of {lat, long} points");
    GeoRing ring;
    for (std::size_t i = 0; i < arr.size(); ++i) ring.push_back(latlong_object(arr[i], idx(f, i)));
    return ring;
  };
  if (!j.contains("polygon")) throw InputError("polygon", "missing");
  raw.area.push_back({GeoPolygon{latlong_ring(j["polygon"], "polygon")}, "polygon"});
  if (j.contains("obstacles")) {
    if (!j["obstacles"].is_array()) throw InputError("obstacles", "expected an array of polygons");
    for (std::size_t i = 0; i < j["obstacles"].size(); ++i)
      raw.nfz.push_back(
          {GeoPolygon{latlong_ring(j["obstacles"][i], idx("obstacles", i))}, idx("obstacles", i)});
  }
  if (!j.contains("scanningDensity")) throw InputError("scanningDensity", "missing");
  raw.spacing = positive(j["scanningDensity"], "scanningDensity");
  if (!j.contains("droneNo")) throw InputError("droneNo", "missing");
  if (!j["droneNo"].is_number_integer() || j["droneNo"].get<long long>() <= 0)
    throw InputError("droneNo", "expected a positive integer");
  parse_uavs(j["droneNo"], raw);
  if (j.contains("pathsStrictlyInPoly")) {
    if (!j["pathsStrictlyInPoly"].is_boolean())
      throw InputError("pathsStrictlyInPoly", "expected true or false");
    raw.mode = j["pathsStrictlyInPoly"].get<bool>() ? Mode::Strict : Mode::Coverage;
  }
  if (j.contains("initialPos") && !(j["initialPos"].is_array() && j["initialPos"].empty())) {
    const json& ip = j["initialPos"];
    if (!ip.is_array() || ip.size() != raw.uavs.size())
      throw InputError("initialPos", "expected one {lat, long} per drone (droneNo = " +
                                         std::to_string(raw.uavs.size()) + ")");
    for (std::size_t i = 0; i < ip.size(); ++i)
      raw.uavs[i].start = latlong_object(ip[i], idx("initialPos", i));
  }
  if (j.contains("rPortions") && !(j["rPortions"].is_array() && j["rPortions"].empty())) {
    const json& rp = j["rPortions"];
    if (!rp.is_array() || rp.size() != raw.uavs.size())
      throw InputError("rPortions",
                       "expected one portion per drone (droneNo = " + std::to_string(raw.uavs.size()) + ")");
    for (std::size_t i = 0; i < rp.size(); ++i) {
      const double s = number(rp[i], idx("rPortions", i));
      if (s < 0) throw InputError(idx("rPortions", i), "must not be negative");
      raw.shares[i] = s;
    }
  }
  return raw;
}

}  // namespace uavcover::mission::detail
