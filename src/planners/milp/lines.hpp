// Graph building of Hong et al. 2021 §3.1, on any free area: per connected part of the free area a
// sweep direction (along its longest boundary edge, a given angle, or the one with the fewest lines),
// virtual lines at the spacing (half a spacing in from the sides), and the segments of each line inside
// the free area (kept 0.5 m from no-fly zones). A segment's two ends are the waypoint pair of
// constraint (7). Regions: the strip of each segment (between the midlines to its neighbours) clipped
// to the free area.
#pragma once

#include <optional>
#include <vector>

#include "planners/boustrophedon/geom.hpp"
#include "uavcover/context.hpp"

namespace uavcover::planners::milp {

enum class Direction { LongestEdge, Auto };

struct Segment {
  Point a, b;    ///< world; a at the low end of the line (frame Y), b at the high end
  int part = 0;  ///< connected part of the free area
  int line = 0;  ///< line index within its part
  [[nodiscard]] double length() const { return boustro::dist(a, b); }
};

struct Part {
  double angle = 0.0;  ///< leg direction, radians counter-clockwise from east
  boustro::Frame frame;
  std::vector<double> xs;  ///< line positions in the frame
  int lines_with_segments = 0;
};

struct Lines {
  std::vector<Part> parts;
  std::vector<Segment> segments;  ///< part by part, line by line, low to high along each line
};

/// Where a segment is cut between two clusters, each of the two legs ends this far short of the cut
/// (the pieces themselves touch, so the regions do): two UAVs never fly to the same point, and their
/// paths do not touch.
inline constexpr double kCutGapM = 0.05;

/// The most lines over the whole area (beyond: the spacing is too small for this planner).
inline constexpr std::size_t kMaxLines = 20000;

/// Lines and segments of `free` (local metres). `fixed`: leg direction (radians counter-clockwise from
/// east) for every part. Throws InputError("spacing_m") beyond kMaxLines.
Lines build_lines(const MultiPolygon& free, const MultiPolygon& no_fly, double spacing, Direction dir,
                  std::optional<double> fixed, const Context& ctx);

/// Neighbours of each segment: the segments of the same part on the neighbouring lines whose spans
/// along the line overlap (their strips share a side), and the last segment of each part with the
/// first of the next part (so that the parts follow each other as in the sweep order). The two pieces
/// of a cut segment (neighbours on one line that touch end to end) are neighbours too.
std::vector<std::vector<int>> adjacency(const Lines& lines);

/// Coverage mode: the segments with each end that lies on the area's outer boundary moved half a
/// footprint further along its line (as the other planners' legs), unless that would come within
/// `clearance` of a no-fly zone. Ends at no-fly zones and holes stay where they are.
std::vector<Segment> extended_for_coverage(const Lines& lines, const MultiPolygon& area,
                                           const MultiPolygon& no_fly, double footprint, double clearance);

/// Per UAV the union of the strips of its segments (owner[s] = UAV of segment s, -1: none), clipped
/// to `free`: exclusive, since the strips are.
std::vector<MultiPolygon> regions(const Lines& lines, const MultiPolygon& free, const std::vector<int>& owner,
                                  int uavs, const Context& ctx);

}  // namespace uavcover::planners::milp
