#include "store/pg_pool.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cstdlib>

namespace uavcover::store::pg {
namespace {

std::string first_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  if (const auto nl = s.find('\n'); nl != std::string::npos) s.resize(nl);
  return s;
}

std::string percent_decode(std::string_view s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      int v = 0;
      const auto [p, ec] = std::from_chars(s.data() + i + 1, s.data() + i + 3, v, 16);
      if (ec == std::errc() && p == s.data() + i + 3) {
        out.push_back(static_cast<char>(v));
        i += 2;
        continue;
      }
    }
    out.push_back(s[i]);
  }
  return out;
}

void replace_all(std::string& s, const std::string& what) {
  if (what.empty()) return;
  for (std::size_t pos = s.find(what); pos != std::string::npos; pos = s.find(what, pos + 3))
    s.replace(pos, what.size(), "***");
}

}  // namespace

Result checked(PGconn* conn, PGresult* raw);

Param text(std::string s) { return Param{std::move(s), false}; }
Param integer(std::int64_t v) { return Param{std::to_string(v), false}; }
Param real(double v) { return Param{fmt::format("{}", v), false}; }
Param boolean(bool v) { return Param{v ? "true" : "false", false}; }
Param bytes(std::string_view b) { return Param{std::string(b), true}; }
Param null() { return Param{std::nullopt, false}; }

std::string Result::str(int row, int col) const {
  return std::string(PQgetvalue(r_.get(), row, col),
                     static_cast<std::size_t>(PQgetlength(r_.get(), row, col)));
}

std::int64_t Result::i64(int row, int col) const {
  const char* v = PQgetvalue(r_.get(), row, col);
  const char* end = v + PQgetlength(r_.get(), row, col);
  std::int64_t out = 0;
  const auto [p, ec] = std::from_chars(v, end, out);
  if (ec != std::errc() || p != end) throw StoreError("database: unexpected integer value");
  return out;
}

double Result::f64(int row, int col) const { return std::strtod(PQgetvalue(r_.get(), row, col), nullptr); }

bool Result::boolean(int row, int col) const { return PQgetvalue(r_.get(), row, col)[0] == 't'; }

Result exec(PGconn* conn, const char* sql, const std::vector<Param>& params, bool binary_result) {
  std::vector<const char*> values;
  std::vector<int> lengths;
  std::vector<int> formats;
  values.reserve(params.size());
  for (const auto& p : params) {
    if (p.value && !p.binary && p.value->find('\0') != std::string::npos)
      throw StoreError("database: a text value contains a NUL byte");
    values.push_back(p.value ? p.value->c_str() : nullptr);
    lengths.push_back(p.value ? static_cast<int>(p.value->size()) : 0);
    formats.push_back(p.binary ? 1 : 0);
  }
  return checked(conn, PQexecParams(conn, sql, static_cast<int>(params.size()), nullptr, values.data(),
                                    lengths.data(), formats.data(), binary_result ? 1 : 0));
}

Result checked(PGconn* conn, PGresult* raw) {
  Result result(raw);
  if (raw == nullptr) throw StoreError("database: " + first_line(PQerrorMessage(conn)));
  const auto status = PQresultStatus(raw);
  if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return result;
  if (PQstatus(conn) != CONNECTION_OK) throw StoreError("database: the connection was lost");
  const char* state = PQresultErrorField(raw, PG_DIAG_SQLSTATE);
  const char* primary = PQresultErrorField(raw, PG_DIAG_MESSAGE_PRIMARY);
  throw PgError("database: " + first_line(primary != nullptr ? primary : PQresultErrorMessage(raw)),
                state != nullptr ? state : "");
}

void exec_script(PGconn* conn, const char* sql) { checked(conn, PQexec(conn, sql)); }

std::string redact(std::string message, const std::string& uri) {
  // user:PASSWORD@host in a URI
  if (const auto scheme = uri.find("://"); scheme != std::string::npos) {
    const auto start = scheme + 3;
    const auto end = uri.find_first_of("/?", start);
    const auto authority = uri.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (const auto at = authority.rfind('@'); at != std::string::npos) {
      const auto userinfo = authority.substr(0, at);
      if (const auto colon = userinfo.find(':'); colon != std::string::npos) {
        const auto password = userinfo.substr(colon + 1);
        replace_all(message, password);
        replace_all(message, percent_decode(password));
      }
    }
  }
  // password=... as a URI query parameter or a conninfo keyword
  for (std::size_t pos = uri.find("password="); pos != std::string::npos;
       pos = uri.find("password=", pos + 1)) {
    const auto start = pos + 9;
    const auto end = uri.find_first_of("& ", start);
    const auto password = uri.substr(start, end == std::string::npos ? std::string::npos : end - start);
    replace_all(message, password);
    replace_all(message, percent_decode(password));
  }
  return message;
}

Conn::~Conn() {
  if (conn_ != nullptr) pool_->release(conn_);
}

Pool::Pool(std::string uri, std::size_t max) : uri_(std::move(uri)), max_(max == 0 ? 1 : max) {}

Pool::~Pool() {
  std::lock_guard lock(mutex_);
  for (PGconn* c : idle_) PQfinish(c);
  idle_.clear();
}

PGconn* Pool::connect() {
  // the URI's own settings (expanded from dbname) override these defaults
  const char* keywords[] = {"connect_timeout", "application_name", "dbname", nullptr};
  const char* values[] = {"10", "uavcover", uri_.c_str(), nullptr};
  PGconn* conn = PQconnectdbParams(keywords, values, 1);
  if (conn == nullptr) throw StoreError("database: out of memory");
  PQsetNoticeProcessor(
      conn, [](void*, const char*) {}, nullptr);  // no NOTICE lines on stderr
  if (PQstatus(conn) != CONNECTION_OK) {
    std::string why = first_line(PQerrorMessage(conn));
    PQfinish(conn);
    throw StoreError("cannot connect to PostgreSQL: " + redact(why, uri_));
  }
  return conn;
}

Conn Pool::acquire() {
  std::unique_lock lock(mutex_);
  available_.wait(lock, [&] { return !idle_.empty() || open_ < max_; });
  if (!idle_.empty()) {
    PGconn* conn = idle_.back();
    idle_.pop_back();
    lock.unlock();
    if (PQstatus(conn) != CONNECTION_OK && !reset(conn)) {
      std::string why = first_line(PQerrorMessage(conn));
      PQfinish(conn);
      {
        std::lock_guard relock(mutex_);
        --open_;
      }
      available_.notify_one();
      throw StoreError("lost the connection to PostgreSQL: " + redact(why, uri_));
    }
    return Conn(this, conn);
  }
  ++open_;
  lock.unlock();
  try {
    return Conn(this, connect());
  } catch (...) {
    {
      std::lock_guard relock(mutex_);
      --open_;
    }
    available_.notify_one();
    throw;
  }
}

bool Pool::reset(PGconn* conn) {
  PQreset(conn);
  return PQstatus(conn) == CONNECTION_OK;
}

void Pool::release(PGconn* conn) {
  const auto tx = PQtransactionStatus(conn);
  if (tx == PQTRANS_INTRANS || tx == PQTRANS_INERROR) PQclear(PQexec(conn, "ROLLBACK"));
  {
    std::lock_guard lock(mutex_);
    idle_.push_back(conn);
  }
  available_.notify_one();
}

}  // namespace uavcover::store::pg
