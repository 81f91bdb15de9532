#include "store/store.hpp"

#include <array>
#include <string_view>

#include "store/backends.hpp"
#include "store/sha256.hpp"

namespace uavcover::store {
namespace {
constexpr std::array<std::string_view, 3> kKinds{"plan", "study", "comparison"};
constexpr std::array<std::string_view, 5> kStates{"queued", "running", "done", "failed", "cancelled"};
}  // namespace

std::string to_string(JobKind kind) { return std::string(kKinds.at(static_cast<std::size_t>(kind))); }
std::string to_string(JobState state) { return std::string(kStates.at(static_cast<std::size_t>(state))); }

JobKind job_kind_from_string(const std::string& s) {
  for (std::size_t i = 0; i < kKinds.size(); ++i)
    if (kKinds[i] == s) return static_cast<JobKind>(i);
  throw std::invalid_argument("unknown job kind \"" + s + "\"");
}

JobState job_state_from_string(const std::string& s) {
  for (std::size_t i = 0; i < kStates.size(); ++i)
    if (kStates[i] == s) return static_cast<JobState>(i);
  throw std::invalid_argument("unknown job state \"" + s + "\"");
}

std::string plan_cache_prefix(const std::vector<ArtifactRef>& artifacts) {
  std::string plan, paths;
  for (const auto& a : artifacts) {
    if (a.name == "plan.json") plan = a.sha256;
    if (a.name == "paths.geojson") paths = a.sha256;
  }
  if (plan.empty() || paths.empty()) return {};
  return sha256_hex(plan + "\n" + paths);
}

void JobCounts::add(JobState state, std::int64_t n) {
  switch (state) {
    case JobState::Queued:
      queued += n;
      break;
    case JobState::Running:
      running += n;
      break;
    case JobState::Done:
      done += n;
      break;
    case JobState::Failed:
      failed += n;
      break;
    case JobState::Cancelled:
      cancelled += n;
      break;
  }
}

std::unique_ptr<Store> open_store(const std::string& url) {
  constexpr std::string_view sqlite = "sqlite:";
  if (url.starts_with(sqlite)) {
    const std::string path = url.substr(sqlite.size());
    if (path.empty()) throw StoreError("--db: sqlite: needs a file path, e.g. sqlite:data/uavcover.db");
    return open_sqlite(path);
  }
  if (url.starts_with("postgresql://") || url.starts_with("postgres://")) return open_postgres(url);
  throw StoreError("--db: expected sqlite:PATH or postgresql://..., got \"" + url + "\"");
}

}  // namespace uavcover::store
