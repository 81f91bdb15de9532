// The planners built into this binary, and the validation of their parameters.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "planners/boustrophedon/boustrophedon.hpp"
#include "planners/darp/darp.hpp"
#ifdef UAVCOVER_HAS_MILP
#include "planners/milp/milp.hpp"
#endif
#ifdef UAVCOVER_HAS_SPIRAL
#include "planners/spiral/spiral.hpp"
#endif
#ifdef UAVCOVER_HAS_SMT
#include "planners/smt/smt.hpp"
#endif
#include "planners/planner.hpp"
#include "uavcover/error.hpp"

namespace uavcover::planners {

namespace {

std::vector<PlannerInfo> builtin() {
  std::vector<PlannerInfo> all;
  // One line per planner module (src/planners/<name>/); optional ones behind their CMake option.
  all.push_back(darp_planner_info());
  all.push_back(boustrophedon_planner_info());
#ifdef UAVCOVER_HAS_MILP
  all.push_back(milp_planner_info());
#endif
#ifdef UAVCOVER_HAS_SPIRAL
  all.push_back(spiral_planner_info());
#endif
#ifdef UAVCOVER_HAS_SMT
  all.push_back(smt_planner_info());
#endif
  return all;
}

const char* type_name(ParamSpec::Type t) {
  switch (t) {
    case ParamSpec::Type::Number:
      return "number";
    case ParamSpec::Type::Integer:
      return "integer";
    case ParamSpec::Type::Boolean:
      return "boolean";
    case ParamSpec::Type::String:
      return "string";
  }
  return "value";
}

std::string number_text(double v) { return fmt::format("{}", v); }

nlohmann::json check_value(const ParamSpec& spec, const nlohmann::json& v) {
  const std::string field = "planner_params." + spec.name;
  switch (spec.type) {
    case ParamSpec::Type::Boolean:
      if (!v.is_boolean()) throw InputError(field, "must be true or false");
      return v;
    case ParamSpec::Type::String: {
      if (!v.is_string()) throw InputError(field, "must be a string");
      const auto s = v.get<std::string>();
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), s) == spec.choices.end()) {
        std::string list;
        for (const auto& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
        throw InputError(field, "must be one of " + list + ", got \"" + s + "\"");
      }
      return v;
    }
    case ParamSpec::Type::Number:
    case ParamSpec::Type::Integer: {
      if (!v.is_number()) throw InputError(field, std::string("must be a ") + type_name(spec.type));
      const double d = v.get<double>();
      if (!std::isfinite(d)) throw InputError(field, "must be finite");
      if (spec.type == ParamSpec::Type::Integer && (d != std::floor(d) || std::fabs(d) > 1e15))
        throw InputError(field, "must be a whole number, got " + number_text(d));
      if (spec.min && d < *spec.min)
        throw InputError(field, "must be >= " + number_text(*spec.min) + ", got " + number_text(d));
      if (spec.max && d > *spec.max)
        throw InputError(field, "must be <= " + number_text(*spec.max) + ", got " + number_text(d));
      if (spec.type == ParamSpec::Type::Integer) return nlohmann::json(static_cast<long long>(d));
      return nlohmann::json(d);
    }
  }
  return v;
}

}  // namespace

ParamSpec param(std::string name, ParamSpec::Type type, nlohmann::json default_value,
                std::optional<double> min, std::optional<double> max, std::string description,
                std::vector<std::string> choices) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = type;
  s.default_value = std::move(default_value);
  s.min = min;
  s.max = max;
  s.choices = std::move(choices);
  s.description = std::move(description);
  return s;
}

const std::vector<PlannerInfo>& registry() {
  static const std::vector<PlannerInfo> all = builtin();
  return all;
}

const PlannerInfo* find(std::string_view name) {
  for (const auto& p : registry())
    if (p.name == name) return &p;
  return nullptr;
}

const PlannerInfo& require(std::string_view name, const std::string& field) {
  if (const PlannerInfo* p = find(name)) return *p;
  std::string list;
  for (const auto& p : registry()) list += (list.empty() ? "" : ", ") + p.name;
  throw InputError(field, "unknown planner \"" + std::string(name) + "\" (available: " + list + ")");
}

nlohmann::json validate_params(const PlannerInfo& planner, const nlohmann::json& params) {
  if (!params.is_null() && !params.is_object()) throw InputError("planner_params", "must be an object");
  nlohmann::json out = nlohmann::json::object();
  if (params.is_object())
    for (auto it = params.begin(); it != params.end(); ++it) {
      const bool known = std::any_of(planner.params.begin(), planner.params.end(),
                                     [&](const ParamSpec& s) { return s.name == it.key(); });
      if (!known) {
        std::string list;
        for (const auto& s : planner.params) list += (list.empty() ? "" : ", ") + s.name;
        throw InputError("planner_params." + it.key(), "unknown parameter of planner \"" + planner.name +
                                                           "\" (known: " + (list.empty() ? "none" : list) +
                                                           ")");
      }
    }
  for (const auto& spec : planner.params) {
    if (params.is_object() && params.contains(spec.name) && !params.at(spec.name).is_null())
      out[spec.name] = check_value(spec, params.at(spec.name));
    else
      out[spec.name] = spec.default_value;
  }
  return out;
}

nlohmann::json describe(const PlannerInfo& planner) {
  nlohmann::json params = nlohmann::json::array();
  for (const auto& s : planner.params) {
    nlohmann::json p = {{"name", s.name},
                        {"type", type_name(s.type)},
                        {"default", s.default_value},
                        {"description", s.description}};
    if (s.min) p["minimum"] = *s.min;
    if (s.max) p["maximum"] = *s.max;
    if (!s.choices.empty()) p["enum"] = s.choices;
    params.push_back(std::move(p));
  }
  const auto& c = planner.supports;
  return {{"name", planner.name},
          {"summary", planner.summary},
          {"params", std::move(params)},
          {"supports",
           {{"shares", c.shares},
            {"no_fly_zones", c.no_fly_zones},
            {"strict_mode", c.strict_mode},
            {"coverage_mode", c.coverage_mode},
            {"multiple_areas", c.multiple_areas},
            {"best_so_far", c.best_so_far},
            {"corridor", c.corridor},
            {"crosshatch", c.crosshatch},
            {"turnaround", c.turnaround},
            {"entry", c.entry},
            {"alternate_transects", c.alternate_transects},
            {"capture_in_turnaround", c.capture_in_turnaround},
            {"structure", c.structure},
            {"oblique", c.oblique}}}};
}

}  // namespace uavcover::planners
