// Validators for every numeric command-line option, as strict as the mission file: a value is
// refused (exit 2, the option named) unless it is written plainly and lies in its documented range
// (docs/limits.md). CLI11 checks the text before converting it, so nothing wraps around (-1 as an
// unsigned), saturates (2^64) or slips through as nan/inf.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>

#include "export/formats.hpp"
#include "uavcover/error.hpp"

namespace uavcover::cli {

/// The largest --max-cells accepted by plan and serve (docs/limits.md): a grid this size already needs
/// gigabytes.
inline constexpr std::size_t kMaxCellsLimit = 1'000'000'000;

namespace detail {

inline std::string shown(const std::string& s) {
  return "'" + s.substr(0, 40) + (s.size() > 40 ? "...'" : "'");
}

// Decimal digits with an optional leading '-' only: no '+', spaces, 0x, exponents or fractions.
inline bool plain_integer(std::string_view s) {
  if (!s.empty() && s.front() == '-') s.remove_prefix(1);
  return !s.empty() && s.find_first_not_of("0123456789") == std::string_view::npos;
}

}  // namespace detail

/// An integer in [lo, hi].
template <class Int>
CLI::Validator integer_in(Int lo, Int hi) {
  static_assert(std::is_integral_v<Int>);
  const std::string range = fmt::format("{}..{}", lo, hi);
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        Int v{};
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (!detail::plain_integer(s) || ec == std::errc::invalid_argument || end != s.data() + s.size())
          return "must be a whole number in " + range + ", got " + detail::shown(s);
        if (ec == std::errc::result_out_of_range || v < lo || v > hi)
          return "must be in " + range + ", got " + detail::shown(s);
        return "";
      },
      "INT in " + range, "integer_in");
}

/// A finite decimal number in the range from lo to hi; `lo_open`/`hi_open` exclude the bound.
/// With `or_zero`, 0 is accepted too (options where 0 means "off" or "automatic").
inline CLI::Validator number_in(double lo, double hi, bool lo_open = false, bool hi_open = false,
                                bool or_zero = false) {
  const std::string range = fmt::format("{}{}, {}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
  const std::string desc = (or_zero ? "0 or " : "") + range;
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        double v = 0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
        if (ec == std::errc::invalid_argument || end != s.data() + s.size() ||
            s.find_first_of("nNiI") != std::string::npos)  // nan, inf, infinity
          return "must be a finite number in " + desc + ", got " + detail::shown(s);
        if (or_zero && ec == std::errc() && v == 0.0) return "";
        if (ec == std::errc::result_out_of_range || v < lo || v > hi || (lo_open && v == lo) ||
            (hi_open && v == hi))
          return "must be in " + desc + ", got " + detail::shown(s);
        return "";
      },
      "NUM in " + desc, "number_in");
}

/// Why `out` cannot be used as an output folder ("" when it can): it must be named, must not be an
/// existing non-folder, and the folder itself (or the nearest existing folder it would be created
/// in) must accept new entries. This is tried by creating and removing an empty probe folder there,
/// which also catches read-only file systems and the super-user's writes to /proc or /sys.
inline std::string output_folder_problem(const std::string& out) {
  namespace fs = std::filesystem;
  if (out.empty()) return "must name a folder, got an empty string";
  std::error_code ec;
  fs::path dir = fs::absolute(fs::path(out), ec).lexically_normal();
  if (ec) return "cannot use '" + out + "': " + ec.message();
  if (!dir.has_filename() && dir.has_relative_path()) dir = dir.parent_path();  // "a/b/" -> "a/b"
  const auto st = fs::status(dir, ec);
  if (fs::exists(st) && !fs::is_directory(st)) return "'" + out + "' exists and is not a folder";
  while (!fs::exists(dir, ec)) {
    if (!dir.has_relative_path()) return "cannot use '" + out + "': no existing parent folder";
    dir = dir.parent_path();
  }
  if (!fs::is_directory(dir, ec))
    return "cannot create the folder '" + out + "': '" + dir.string() + "' is a file, not a folder";
  std::string probe = (dir / ".uavcover-probe-XXXXXX").string();
  if (::mkdtemp(probe.data()) == nullptr)
    return "cannot write in '" + dir.string() + "': " + std::strerror(errno);
  ::rmdir(probe.c_str());
  return "";
}

/// An output folder (see output_folder_problem), checked before any work is done.
inline CLI::Validator output_folder() {
  return CLI::Validator([](std::string& s) { return output_folder_problem(s); }, "DIR", "output_folder");
}

/// One entry of --format / --export: a format of the export table (exporting::formats(); any case),
/// refused with the table's names ("unknown format \"gpx\" (known: geojson, qgc, ...)").
inline CLI::Validator export_format() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        try {
          (void)exporting::parse_formats({s});
          return "";
        } catch (const InputError& e) {
          const std::string what = e.what();
          return e.field().empty() ? what : what.substr(e.field().size() + 2);
        }
      },
      "{" + exporting::format_list() + "}", "export_format");
}

/// "qgc, wpl, ..." : the formats that ExportOptions::per_sortie splits (Format::per_sortie).
inline std::string per_sortie_format_list() {
  std::string list;
  for (const auto& f : exporting::formats())
    if (f.per_sortie) list += (list.empty() ? "" : ", ") + std::string(f.name);
  return list;
}

}  // namespace uavcover::cli
