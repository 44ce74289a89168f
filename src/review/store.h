#pragma once
// The review study's durable store: one SQLite file (WAL journal, synchronous=FULL, every write
// in a transaction, schema version recorded). It holds the participants with their secret tokens,
// the clip list the server registered, questionnaire and free-text answers and the ratings.
// Every statement is parameterised; the class serialises access with a mutex so one instance can
// serve all HTTP worker threads.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

struct sqlite3;

namespace wheelpose::review {

inline constexpr int kSchemaVersion = 1;

struct Participant {
  std::int64_t id = 0;
  std::string name;
  std::string token;
  std::string created_at;
  std::string consent_at;                // empty until consent is given
  std::vector<std::string> group_order;  // empty until first assigned
  std::string finished_at;
};

struct ClipRecord {
  std::string id;     // "<group>/<file stem>"
  std::string group;  // folder name given to `serve --clips`
  int position = 0;   // order inside the group
  std::string path;   // absolute path of the seated-clip JSON
};

// One participant's answers to one clip; a question not yet answered is nullopt.
struct Rating {
  std::int64_t participant_id = 0;
  std::string clip_id;
  std::optional<int> q1;   // ease, 1 (cannot perform at all) .. 7 (without any difficulty)
  std::optional<int> q2;   // frequency, 1 (never) .. 7 (every day)
  std::optional<bool> q3;  // seen other wheelchair users perform it
  std::string updated_at;
  bool complete() const { return q1 && q2 && q3; }
};

class ReviewStore {
 public:
  // Opens (creating if needed) the database. `created` tells whether this call created it, so the
  // caller can print the new admin token once.
  explicit ReviewStore(const std::filesystem::path& path, bool* created = nullptr);
  ~ReviewStore();
  ReviewStore(const ReviewStore&) = delete;
  ReviewStore& operator=(const ReviewStore&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string admin_token() const;
  // Seed of the per-participant group shuffles (drawn from /dev/urandom when the DB is created).
  std::uint64_t study_seed() const;

  // Throws Error if the name is empty, too long or already taken.
  Participant add_participant(const std::string& name);
  std::vector<Participant> participants() const;
  std::optional<Participant> participant_by_name(const std::string& name) const;
  // Compares the token with every participant's in constant time per comparison.
  std::optional<Participant> participant_by_token(const std::string& token) const;
  void set_consent(std::int64_t participant);
  // Records the order the first time; later calls return the recorded order unchanged.
  std::vector<std::string> assign_group_order(std::int64_t participant,
                                              const std::vector<std::string>& order);
  void set_finished(std::int64_t participant);

  // Replaces the registered clip list (one transaction).
  void register_clips(const std::vector<ClipRecord>& clips);
  std::vector<ClipRecord> clips() const;

  // JSON object texts, validated by the caller.
  void set_questionnaire(std::int64_t participant, const std::string& json);
  std::string questionnaire(std::int64_t participant) const;  // "" if none
  void set_free_text(std::int64_t participant, const std::string& json);
  std::string free_text(std::int64_t participant) const;

  // Upserts the answers given (nullopt fields keep their stored value).
  void save_rating(const Rating& rating);
  std::vector<Rating> ratings(std::optional<std::int64_t> participant = std::nullopt) const;

 private:
  std::string meta(const std::string& key) const;
  void set_answers(const char* table, std::int64_t participant, const std::string& json);
  std::string answers(const char* table, std::int64_t participant) const;
  std::filesystem::path path_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
};

// 32 random bytes from /dev/urandom as 64 lowercase hex digits.
std::string random_token();
// Equal-length-independent comparison whose time does not depend on where the strings differ.
bool constant_time_equal(const std::string& a, const std::string& b);

}  // namespace wheelpose::review
