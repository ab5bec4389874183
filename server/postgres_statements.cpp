#include "server/postgres_statements.h"

#include <endian.h>

#include <cstring>
#include <stdexcept>

namespace penumbra::server::pg {

Params& Params::add(int64_t value) {
  const uint64_t big = htobe64(uint64_t(value));
  return push(std::string(reinterpret_cast<const char*>(&big), 8), kInt8, false);
}

std::vector<const char*> Params::values() const {
  std::vector<const char*> out;
  for (size_t i = 0; i < bytes_.size(); ++i) out.push_back(null_[i] ? nullptr : bytes_[i].data());
  return out;
}

std::vector<int> Params::lengths() const {
  std::vector<int> out;
  for (const std::string& b : bytes_) out.push_back(int(b.size()));
  return out;
}

Params& Params::push(std::string value, Oid type, bool null) {
  bytes_.push_back(std::move(value));
  types_.push_back(type);
  null_.push_back(null);
  return *this;
}

std::string errorOf(PGconn* conn) {
  std::string message = PQerrorMessage(conn);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

Result run(PGconn* conn, const char* sql, const Params& params) {
  const std::vector<const char*> values = params.values();
  const std::vector<int> lengths = params.lengths(), formats = params.formats();
  Result result(PQexecParams(conn, sql, params.count(), params.types(), values.data(),
                             lengths.data(), formats.data(), 1),
                &PQclear);
  const ExecStatusType status = result ? PQresultStatus(result.get()) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK)
    throw std::runtime_error(std::string(sql).substr(0, 40) + ": " + errorOf(conn));
  return result;
}

void runScript(PGconn* conn, const char* sql) {
  const Result result(PQexec(conn, sql), &PQclear);
  if (!result || PQresultStatus(result.get()) != PGRES_COMMAND_OK)
    throw std::runtime_error(std::string(sql).substr(0, 40) + ": " + errorOf(conn));
}

int64_t int8At(const PGresult* result, int row, int column) {
  uint64_t big = 0;
  std::memcpy(&big, PQgetvalue(result, row, column), sizeof big);
  return int64_t(be64toh(big));
}

std::optional<int64_t> optionalInt8At(const PGresult* result, int row, int column) {
  if (PQgetisnull(result, row, column)) return std::nullopt;
  return int8At(result, row, column);
}

std::string bytesAt(const PGresult* result, int row, int column) {
  return std::string(PQgetvalue(result, row, column), size_t(PQgetlength(result, row, column)));
}

void eachRow(PGconn* conn, const char* sql, const Params& params,
             const std::function<void(const PGresult*)>& row) {
  const std::vector<const char*> values = params.values();
  const std::vector<int> lengths = params.lengths(), formats = params.formats();
  if (!PQsendQueryParams(conn, sql, params.count(), params.types(), values.data(), lengths.data(),
                         formats.data(), 1) ||
      !PQsetSingleRowMode(conn))
    throw std::runtime_error(std::string(sql).substr(0, 40) + ": " + errorOf(conn));
  std::string error;
  // Every result is read, even after an error, so that the connection is ready for the next.
  while (PGresult* next = PQgetResult(conn)) {
    const Result result(next, &PQclear);
    const ExecStatusType status = PQresultStatus(next);
    if (status == PGRES_SINGLE_TUPLE && error.empty()) {
      try {
        row(next);
      } catch (const std::exception& thrown) {
        error = thrown.what();
      }
    } else if (status != PGRES_TUPLES_OK && status != PGRES_SINGLE_TUPLE && error.empty()) {
      error = std::string(sql).substr(0, 40) + ": " + errorOf(conn);
    }
  }
  if (!error.empty()) throw std::runtime_error(error);
}

}  // namespace penumbra::server::pg
