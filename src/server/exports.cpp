#include "server/exports.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/post.hpp>

#include "uavcover/error.hpp"
#include "usecases/plan_outputs.hpp"

namespace uavcover::server {
namespace {

/// The entry's own file in the cache: its warnings and refusal (a refused format caches this alone).
const std::string kMeta = ".meta.json";

}  // namespace

ExportService::ExportService(store::Store& store, ExportConfig config)
    : store_(store),
      config_(std::move(config)),
      pool_(static_cast<std::size_t>(std::max(1, config_.threads))) {}

ExportService::~ExportService() { pool_.join(); }

std::int64_t ExportService::builds() const {
  std::lock_guard lock(mutex_);
  return builds_;
}

int ExportService::waiting(const std::string& key) const {
  std::lock_guard lock(mutex_);
  const auto it = waiting_.find(key);
  return it == waiting_.end() ? 0 : it->second;
}

std::shared_ptr<const ExportEntry> ExportService::from_cache(const std::string& key) {
  const auto refs = store_.cache_entry(key);
  if (!refs) return nullptr;
  auto e = std::make_shared<ExportEntry>();
  e->key = key;
  bool has_meta = false;
  for (const auto& r : *refs)
    if (r.name == kMeta)
      has_meta = true;
    else
      e->names.push_back(r.name);
  if (!has_meta) return nullptr;  // not one of ours: build it again
  const auto meta = store_.cached_file(key, kMeta);
  if (!meta) return nullptr;  // evicted meanwhile
  try {
    const auto j = nlohmann::json::parse(meta->bytes);
    e->warnings = j.at("warnings").get<std::vector<std::string>>();
    e->refused_field = j.at("refused_field").get<std::string>();
    e->refused = j.at("refused").get<std::string>();
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
  return e;
}

std::shared_ptr<const ExportEntry> ExportService::build(const store::Job& job, const std::string& key,
                                                        const std::string& format,
                                                        const usecases::ExportVariant& variant) {
  if (config_.before_build) config_.before_build(key);
  const auto plan = store_.get_artifact(job.id, "plan.json");
  const auto paths = store_.get_artifact(job.id, "paths.geojson");
  if (!plan || !paths)
    throw OperationError("plan " + std::to_string(job.id) + " has no stored plan.json and paths.geojson");
  double step = 0;  // a plan job's trajectory_step_s: the sampled trajectory CSV
  if (const auto it = job.params.find("trajectory_step_s"); it != job.params.end() && it->is_number())
    step = it->get<double>();
  usecases::BuiltExport built = usecases::build_export(
      plan->bytes, paths->bytes, format, step, {},
      [this](Mission& m) { load_server_terrain(m, store_, config_.dem_dir); }, variant);
  auto e = std::make_shared<ExportEntry>();
  e->key = key;
  for (const auto& f : built.files) e->names.push_back(f.name);
  std::sort(e->names.begin(), e->names.end());
  e->warnings = std::move(built.warnings);
  e->refused_field = std::move(built.refused_field);
  e->refused = std::move(built.refused);
  Artifacts cached = built.files;
  const nlohmann::json meta = {
      {"warnings", e->warnings}, {"refused_field", e->refused_field}, {"refused", e->refused}};
  cached.push_back({kMeta, "application/json", meta.dump()});
  e->files = std::make_shared<const Artifacts>(std::move(built.files));
  try {
    if (!store_.put_cache(key, cached, config_.cache_cap_bytes))
      spdlog::info("export {}: {} bytes, over the cache's cap; served without caching", key, [&] {
        std::size_t n = 0;
        for (const auto& f : cached) n += f.bytes.size();
        return n;
      }());
  } catch (const std::exception& ex) {
    spdlog::warn("export {}: cannot cache it: {}", key, ex.what());
  }
  return e;
}

std::shared_ptr<const ExportEntry> ExportService::get(const store::Job& job, const std::string& format,
                                                      const usecases::ExportVariant& asked) {
  // what the format reads of the client's options: ?method= on a .plan is the plain .plan's entry
  const usecases::ExportVariant variant = asked.for_format(format);
  const std::string prefix = store::plan_cache_prefix(job.artifacts);
  if (prefix.empty()) return nullptr;
  // the trajectory of a job with trajectory_step_s is sampled: its own entry
  std::string key = prefix + "/" + format;
  if (const auto it = job.params.find("trajectory_step_s");
      format == "trajectory" && it != job.params.end() && it->is_number())
    key += "@" + it->dump();
  key += variant.key();
  std::shared_future<std::shared_ptr<const ExportEntry>> future;
  {
    std::unique_lock lock(mutex_);
    auto it = inflight_.find(key);
    if (it == inflight_.end()) {
      lock.unlock();
      if (auto cached = from_cache(key)) return cached;
      lock.lock();
      it = inflight_.find(key);  // another caller may have started it meanwhile
    }
    if (it == inflight_.end()) {
      auto promise = std::make_shared<std::promise<std::shared_ptr<const ExportEntry>>>();
      it = inflight_.emplace(key, promise->get_future().share()).first;
      ++builds_;
      boost::asio::post(pool_, [this, promise, job, key, format, variant] {
        try {
          promise->set_value(build(job, key, format, variant));
        } catch (...) {
          promise->set_exception(std::current_exception());
        }
        std::lock_guard done(mutex_);
        inflight_.erase(key);
      });
    }
    future = it->second;
    ++waiting_[key];
  }
  struct Leave {
    ExportService& s;
    const std::string& key;
    ~Leave() {
      std::lock_guard lock(s.mutex_);
      if (--s.waiting_[key] == 0) s.waiting_.erase(key);
    }
  } leave{*this, key};
  return future.get();
}

std::optional<Artifact> ExportService::read(const ExportEntry& entry, const store::Job& job,
                                            const std::string& format, const std::string& name,
                                            const usecases::ExportVariant& variant) {
  if (std::find(entry.names.begin(), entry.names.end(), name) == entry.names.end()) return std::nullopt;
  if (entry.files)
    for (const auto& f : *entry.files)
      if (f.name == name) return f;
  if (auto a = store_.cached_file(entry.key, name)) return a;
  // evicted between the entry and its file: built again
  const auto again = get(job, format, variant);
  if (!again) return std::nullopt;
  if (std::find(again->names.begin(), again->names.end(), name) == again->names.end()) return std::nullopt;
  if (again->files)
    for (const auto& f : *again->files)
      if (f.name == name) return f;
  return store_.cached_file(again->key, name);
}

}  // namespace uavcover::server
