// libpq plumbing for the PostgreSQL store: a small thread-safe connection pool, parameterised queries
// (text parameters, binary bytea where asked) and results. Errors become StoreError with a short
// message that never carries the connection URI's password.
#pragma once

#include <libpq-fe.h>

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "store/store.hpp"

namespace uavcover::store::pg {

/// A database error with its SQLSTATE ("40P01" deadlock, "40001" serialization failure, ...).
struct PgError : StoreError {
  PgError(const std::string& message, std::string state) : StoreError(message), sqlstate(std::move(state)) {}
  std::string sqlstate;
};

/// One query parameter: text (or SQL NULL), or raw bytes sent in binary format (for bytea).
struct Param {
  std::optional<std::string> value;
  bool binary = false;
};
Param text(std::string s);
Param integer(std::int64_t v);
Param real(double v);
Param boolean(bool v);
Param bytes(std::string_view b);
Param null();

/// A query result (owns the PGresult).
class Result {
 public:
  explicit Result(PGresult* r) : r_(r, &PQclear) {}
  [[nodiscard]] int rows() const { return PQntuples(r_.get()); }
  [[nodiscard]] bool is_null(int row, int col) const { return PQgetisnull(r_.get(), row, col) != 0; }
  [[nodiscard]] std::string str(int row, int col) const;
  [[nodiscard]] std::int64_t i64(int row, int col) const;
  [[nodiscard]] int i32(int row, int col) const { return static_cast<int>(i64(row, col)); }
  [[nodiscard]] double f64(int row, int col) const;
  [[nodiscard]] bool boolean(int row, int col) const;

 private:
  std::unique_ptr<PGresult, void (*)(PGresult*)> r_;
};

/// Runs one parameterised statement. `binary_result`: all columns come back in binary format (raw
/// bytes for bytea and text columns). Throws PgError (or StoreError when the connection is lost).
Result exec(PGconn* conn, const char* sql, const std::vector<Param>& params = {}, bool binary_result = false);

/// Runs a constant script of several statements (migrations only: no parameters).
void exec_script(PGconn* conn, const char* sql);

/// Removes the password (user:PASSWORD@ or password=...) from a message about `uri`.
std::string redact(std::string message, const std::string& uri);

class Pool;

/// A connection taken from the pool; returned (rolled back if a transaction is still open) on
/// destruction.
class Conn {
 public:
  Conn(Pool* pool, PGconn* conn) : pool_(pool), conn_(conn) {}
  Conn(const Conn&) = delete;
  Conn& operator=(const Conn&) = delete;
  ~Conn();
  [[nodiscard]] PGconn* get() const { return conn_; }

 private:
  Pool* pool_;
  PGconn* conn_;
};

/// Up to `max` connections, opened lazily. A broken connection is reset once when taken.
class Pool {
 public:
  Pool(std::string uri, std::size_t max);
  ~Pool();
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  Conn acquire();
  /// Resets a connection that broke (PQreset); false when it stays broken.
  bool reset(PGconn* conn);
  [[nodiscard]] const std::string& uri() const { return uri_; }

 private:
  friend class Conn;
  void release(PGconn* conn);
  PGconn* connect();

  std::string uri_;
  std::size_t max_;
  std::mutex mutex_;
  std::condition_variable available_;
  std::vector<PGconn*> idle_;
  std::size_t open_ = 0;
};

}  // namespace uavcover::store::pg
