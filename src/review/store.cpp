#include "review/store.h"

#include <sqlite3.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace wheelpose::review {
namespace {

// A prepared statement bound by position; finalised on scope exit.
class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const std::filesystem::path& path)
      : db_(db), path_(path) {
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) fail("prepare");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Statement& bind(int i, std::int64_t v) {
    sqlite3_bind_int64(stmt_, i, v);
    return *this;
  }
  Statement& bind_opt(int i, std::optional<int> v) {
    if (v) {
      sqlite3_bind_int(stmt_, i, *v);
    } else {
      sqlite3_bind_null(stmt_, i);
    }
    return *this;
  }
  // True while a row is available.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail("step");
  }
  void run() {
    while (step()) {
    }
  }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
  }
  std::int64_t integer(int col) const { return sqlite3_column_int64(stmt_, col); }
  bool is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }

 private:
  [[noreturn]] void fail(const char* what) {
    throw Error(path_.string() + ": SQLite " + what + " failed: " + sqlite3_errmsg(db_),
                ErrorKind::kFailure);
  }
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  const std::filesystem::path& path_;
};

void exec(sqlite3* db, const char* sql, const std::filesystem::path& path) {
  char* err = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    throw Error(path.string() + ": SQLite: " + msg, ErrorKind::kFailure);
  }
}

// BEGIN IMMEDIATE ... COMMIT, rolled back if the scope is left by an exception.
class Transaction {
 public:
  Transaction(sqlite3* db, const std::filesystem::path& path) : db_(db), path_(path) {
    exec(db_, "BEGIN IMMEDIATE", path_);
  }
  ~Transaction() {
    if (!done_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  void commit() {
    exec(db_, "COMMIT", path_);
    done_ = true;
  }

 private:
  sqlite3* db_;
  const std::filesystem::path& path_;
  bool done_ = false;
};

std::string now_utc() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL);
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS participants (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL UNIQUE,
  token TEXT NOT NULL UNIQUE,
  created_at TEXT NOT NULL,
  consent_at TEXT NOT NULL DEFAULT '',
  group_order TEXT NOT NULL DEFAULT '[]',
  finished_at TEXT NOT NULL DEFAULT ''
);
CREATE TABLE IF NOT EXISTS clips (
  id TEXT PRIMARY KEY,
  group_name TEXT NOT NULL,
  position INTEGER NOT NULL,
  path TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS questionnaire (
  participant_id INTEGER PRIMARY KEY REFERENCES participants(id),
  answers TEXT NOT NULL,
  updated_at TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS free_text (
  participant_id INTEGER PRIMARY KEY REFERENCES participants(id),
  answers TEXT NOT NULL,
  updated_at TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS ratings (
  participant_id INTEGER NOT NULL REFERENCES participants(id),
  clip_id TEXT NOT NULL,
  q1 INTEGER CHECK (q1 BETWEEN 1 AND 7),
  q2 INTEGER CHECK (q2 BETWEEN 1 AND 7),
  q3 INTEGER CHECK (q3 IN (0, 1)),
  updated_at TEXT NOT NULL,
  PRIMARY KEY (participant_id, clip_id)
);
)sql";

Participant read_participant(const Statement& s) {
  Participant p;
  p.id = s.integer(0);
  p.name = s.text(1);
  p.token = s.text(2);
  p.created_at = s.text(3);
  p.consent_at = s.text(4);
  const auto order = nlohmann::json::parse(s.text(5), nullptr, false);
  if (order.is_array()) {
    for (const auto& g : order) {
      if (g.is_string()) p.group_order.push_back(g.get<std::string>());
    }
  }
  p.finished_at = s.text(6);
  return p;
}

constexpr const char* kParticipantColumns =
    "SELECT id, name, token, created_at, consent_at, group_order, finished_at FROM participants";

}  // namespace

std::string random_token() {
  std::ifstream in("/dev/urandom", std::ios::binary);
  unsigned char bytes[32];
  if (!in.read(reinterpret_cast<char*>(bytes), sizeof bytes)) {
    throw Error("/dev/urandom: cannot read random bytes for a token", ErrorKind::kFailure);
  }
  std::string hex;
  char buf[3];
  for (unsigned char b : bytes) {
    std::snprintf(buf, sizeof buf, "%02x", b);
    hex += buf;
  }
  return hex;
}

bool constant_time_equal(const std::string& a, const std::string& b) {
  // Walk the longer length so the time depends only on the lengths, never on the contents.
  const std::size_t n = std::max(a.size(), b.size());
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    diff |= x ^ y;
  }
  return diff == 0;
}

ReviewStore::ReviewStore(const std::filesystem::path& path, bool* created) : path_(path) {
  const bool existed = std::filesystem::exists(path);
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw Error(path.string() + ": cannot open the review database: " + msg, ErrorKind::kFailure);
  }
  try {
    sqlite3_busy_timeout(db_, 10000);
    // WAL lets `review status` read while the server writes; FULL syncs every commit so an
    // acknowledged answer survives even a power cut, not just a killed process.
    exec(db_, "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;", path_);
    Transaction tx(db_, path_);
    exec(db_, kSchema, path_);
    bool fresh = false;
    {
      Statement s(db_, "SELECT version FROM schema_version", path_);
      if (s.step()) {
        if (s.integer(0) != kSchemaVersion) {
          throw Error(path.string() + ": review database schema version " +
                      std::to_string(s.integer(0)) + ", this build reads version " +
                      std::to_string(kSchemaVersion));
        }
      } else {
        fresh = true;
      }
    }
    if (fresh) {
      if (existed && std::filesystem::file_size(path) > 0) {
        // An existing non-empty file without our version row is some other database.
        Statement c(db_, "SELECT count(*) FROM participants", path_);
        c.step();
        if (c.integer(0) > 0) throw Error(path.string() + ": not a wheelpose review database");
      }
      Statement(db_, "INSERT INTO schema_version (version) VALUES (?)", path_)
          .bind(1, std::int64_t{kSchemaVersion})
          .run();
      Statement(db_, "INSERT INTO meta (key, value) VALUES ('admin_token', ?)", path_)
          .bind(1, random_token())
          .run();
      Statement(db_, "INSERT INTO meta (key, value) VALUES ('study_seed', ?)", path_)
          .bind(1, random_token().substr(0, 16))
          .run();
      Statement(db_, "INSERT INTO meta (key, value) VALUES ('created_at', ?)", path_)
          .bind(1, now_utc())
          .run();
    }
    tx.commit();
    if (created) *created = fresh;
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

ReviewStore::~ReviewStore() { sqlite3_close(db_); }

std::string ReviewStore::meta(const std::string& key) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT value FROM meta WHERE key = ?", path_);
  s.bind(1, key);
  return s.step() ? s.text(0) : std::string();
}

std::string ReviewStore::admin_token() const { return meta("admin_token"); }

std::uint64_t ReviewStore::study_seed() const {
  return std::stoull(meta("study_seed"), nullptr, 16);
}

Participant ReviewStore::add_participant(const std::string& name) {
  if (name.empty() || name.size() > 100) {
    throw Error("participant name must be 1 to 100 characters, got " + std::to_string(name.size()));
  }
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  {
    Statement s(db_, "SELECT 1 FROM participants WHERE name = ?", path_);
    s.bind(1, name);
    if (s.step()) throw Error(path_.string() + ": participant '" + name + "' already exists");
  }
  Participant p;
  p.name = name;
  p.token = random_token();
  p.created_at = now_utc();
  Statement(db_, "INSERT INTO participants (name, token, created_at) VALUES (?, ?, ?)", path_)
      .bind(1, p.name)
      .bind(2, p.token)
      .bind(3, p.created_at)
      .run();
  p.id = sqlite3_last_insert_rowid(db_);
  tx.commit();
  return p;
}

std::vector<Participant> ReviewStore::participants() const {
  std::lock_guard lock(mutex_);
  Statement s(db_, (std::string(kParticipantColumns) + " ORDER BY id").c_str(), path_);
  std::vector<Participant> out;
  while (s.step()) out.push_back(read_participant(s));
  return out;
}

std::optional<Participant> ReviewStore::participant_by_name(const std::string& name) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, (std::string(kParticipantColumns) + " WHERE name = ?").c_str(), path_);
  s.bind(1, name);
  if (s.step()) return read_participant(s);
  return std::nullopt;
}

std::optional<Participant> ReviewStore::participant_by_token(const std::string& token) const {
  std::optional<Participant> found;
  // Compare against every row (no early exit, no SQL lookup by secret) so timing reveals nothing.
  for (auto& p : participants()) {
    if (constant_time_equal(p.token, token) && !found) found = std::move(p);
  }
  return found;
}

void ReviewStore::set_consent(std::int64_t participant) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  Statement(db_, "UPDATE participants SET consent_at = ? WHERE id = ? AND consent_at = ''", path_)
      .bind(1, now_utc())
      .bind(2, participant)
      .run();
  tx.commit();
}

std::vector<std::string> ReviewStore::assign_group_order(std::int64_t participant,
                                                         const std::vector<std::string>& order) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  Statement s(db_, "SELECT group_order FROM participants WHERE id = ?", path_);
  s.bind(1, participant);
  if (!s.step()) throw Error("unknown participant id " + std::to_string(participant));
  const auto stored = nlohmann::json::parse(s.text(0), nullptr, false);
  if (stored.is_array() && !stored.empty()) return stored.get<std::vector<std::string>>();
  Statement(db_, "UPDATE participants SET group_order = ? WHERE id = ?", path_)
      .bind(1, nlohmann::json(order).dump())
      .bind(2, participant)
      .run();
  tx.commit();
  return order;
}

void ReviewStore::set_finished(std::int64_t participant) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  Statement(db_, "UPDATE participants SET finished_at = ? WHERE id = ? AND finished_at = ''", path_)
      .bind(1, now_utc())
      .bind(2, participant)
      .run();
  tx.commit();
}

void ReviewStore::register_clips(const std::vector<ClipRecord>& clips) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  exec(db_, "DELETE FROM clips", path_);
  for (const auto& c : clips) {
    Statement(db_, "INSERT INTO clips (id, group_name, position, path) VALUES (?, ?, ?, ?)", path_)
        .bind(1, c.id)
        .bind(2, c.group)
        .bind(3, std::int64_t{c.position})
        .bind(4, c.path)
        .run();
  }
  tx.commit();
}

std::vector<ClipRecord> ReviewStore::clips() const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, group_name, position, path FROM clips ORDER BY group_name, position",
              path_);
  std::vector<ClipRecord> out;
  while (s.step()) {
    out.push_back({s.text(0), s.text(1), static_cast<int>(s.integer(2)), s.text(3)});
  }
  return out;
}

// Questionnaire and free-text answers share one shape: a JSON text per participant, replaced on
// every save. `table` is one of the two fixed names below, never user input.
void ReviewStore::set_answers(const char* table, std::int64_t participant,
                              const std::string& json) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  const std::string sql = std::string("INSERT INTO ") + table +
                          " (participant_id, answers, updated_at) VALUES (?, ?, ?) "
                          "ON CONFLICT (participant_id) DO UPDATE SET "
                          "answers = excluded.answers, updated_at = excluded.updated_at";
  Statement(db_, sql.c_str(), path_).bind(1, participant).bind(2, json).bind(3, now_utc()).run();
  tx.commit();
}

std::string ReviewStore::answers(const char* table, std::int64_t participant) const {
  std::lock_guard lock(mutex_);
  const std::string sql = std::string("SELECT answers FROM ") + table + " WHERE participant_id = ?";
  Statement s(db_, sql.c_str(), path_);
  s.bind(1, participant);
  return s.step() ? s.text(0) : std::string();
}

void ReviewStore::set_questionnaire(std::int64_t participant, const std::string& json) {
  set_answers("questionnaire", participant, json);
}

std::string ReviewStore::questionnaire(std::int64_t participant) const {
  return answers("questionnaire", participant);
}

void ReviewStore::set_free_text(std::int64_t participant, const std::string& json) {
  set_answers("free_text", participant, json);
}

std::string ReviewStore::free_text(std::int64_t participant) const {
  return answers("free_text", participant);
}

void ReviewStore::save_rating(const Rating& r) {
  std::lock_guard lock(mutex_);
  Transaction tx(db_, path_);
  std::optional<int> q3;
  if (r.q3) q3 = *r.q3 ? 1 : 0;
  Statement(db_,
            "INSERT INTO ratings (participant_id, clip_id, q1, q2, q3, updated_at) "
            "VALUES (?, ?, ?, ?, ?, ?) ON CONFLICT (participant_id, clip_id) DO UPDATE SET "
            "q1 = coalesce(excluded.q1, q1), q2 = coalesce(excluded.q2, q2), "
            "q3 = coalesce(excluded.q3, q3), updated_at = excluded.updated_at",
            path_)
      .bind(1, r.participant_id)
      .bind(2, r.clip_id)
      .bind_opt(3, r.q1)
      .bind_opt(4, r.q2)
      .bind_opt(5, q3)
      .bind(6, now_utc())
      .run();
  tx.commit();
}

std::vector<Rating> ReviewStore::ratings(std::optional<std::int64_t> participant) const {
  std::lock_guard lock(mutex_);
  const char* sql = participant
                        ? "SELECT participant_id, clip_id, q1, q2, q3, updated_at FROM ratings "
                          "WHERE participant_id = ? ORDER BY participant_id, clip_id"
                        : "SELECT participant_id, clip_id, q1, q2, q3, updated_at FROM ratings "
                          "ORDER BY participant_id, clip_id";
  Statement s(db_, sql, path_);
  if (participant) s.bind(1, *participant);
  std::vector<Rating> out;
  while (s.step()) {
    Rating r;
    r.participant_id = s.integer(0);
    r.clip_id = s.text(1);
    if (!s.is_null(2)) r.q1 = static_cast<int>(s.integer(2));
    if (!s.is_null(3)) r.q2 = static_cast<int>(s.integer(3));
    if (!s.is_null(4)) r.q3 = s.integer(4) != 0;
    r.updated_at = s.text(5);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace wheelpose::review
