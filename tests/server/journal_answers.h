// Shared by the journal restart tests: a scene's served meshes, whole and every `since` delta,
// to compare byte for byte across a restart, and raw SQL on a test data directory's journal.
#pragma once

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <map>
#include <string>
#include <vector>

#include "server_fixture.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {

using Answers = std::map<std::string, std::string>;  // query → body

// The scene's whole binary mesh, as the page loads it.
inline std::string meshBin(TestClient& client, const std::string& id) {
  const auto res = client.Get(("/api/scenes/" + id + "/mesh?format=bin").c_str());
  EXPECT_TRUE(res && res->status == 200);
  return res ? res->body : "";
}

// The binary mesh (and, with `wholeJson`, the JSON one) and every delta since 0..last, binary
// and JSON.
inline Answers served(TestClient& client, const std::string& id, uint64_t last, bool wholeJson) {
  Answers out;
  std::vector<std::string> queries = {"?format=bin"};
  if (wholeJson) queries.push_back("");
  for (uint64_t since = 0; since <= last; ++since) {
    queries.push_back("?format=bin&since=" + std::to_string(since));
    queries.push_back("?since=" + std::to_string(since));
  }
  for (const std::string& query : queries) {
    const auto res = client.Get(("/api/scenes/" + id + "/mesh" + query).c_str());
    EXPECT_TRUE(res && res->status == 200) << query;
    out[query] = res ? res->body : "";
  }
  return out;
}

// Runs `statement` on the data directory's journal (the server stopped).
inline void sql(const TempDataDir& data, const std::string& statement) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((data.str() + "/journal.sqlite3").c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, statement.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
      << statement << ": " << sqlite3_errmsg(db);
  sqlite3_close(db);
}

}  // namespace penumbra::server::test
