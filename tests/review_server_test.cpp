// End-to-end tests of `wheelpose review serve`: the server runs as a child process of the test;
// requests go over HTTP. Covers authorisation, input validation and a load test with a kill -9 in
// the middle (no acknowledged answer may be lost).

#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "cli_runner.h"
#include "http_probe.h"
#include "motion/clip_json.h"
#include "review/store.h"

// After Eigen (via motion/): <resolv.h>, pulled in by httplib, defines a macro named _res.
#include <httplib.h>

namespace wheelpose {
namespace {

using nlohmann::json;
using testing::free_port;
using testing::fresh_temp_dir;
using testing::read_text;

// A tiny valid seated clip: rest pose, root moving up by `frame` millimetres.
void write_clip(const std::filesystem::path& path, int frames) {
  motion::SeatedClip clip;
  clip.motion.name = path.stem().string();
  clip.motion.fps = 20.0;
  for (int j = 1; j < motion::kJointCount; ++j) {
    clip.motion.rest_offsets[j] = motion::rest_direction(j) * motion::default_bone_length(j);
  }
  for (int f = 0; f < frames; ++f) {
    clip.motion.root_positions.emplace_back(0.0, 0.5 + 0.001 * f, 0.0);
    motion::PoseRotations rotations;
    rotations.fill(Eigen::Quaterniond::Identity());
    clip.motion.local_rotations.push_back(rotations);
  }
  clip.positions = motion::forward_kinematics(clip.motion);
  clip.provenance = nlohmann::ordered_json::object();
  motion::write_seated_clip_json(clip, path);
}

// Two groups g1, g2 of `per_group` clips each: ids g1/c000 ...
std::vector<std::string> make_clips(const std::filesystem::path& dir, int per_group) {
  std::vector<std::string> ids;
  for (const char* g : {"g1", "g2"}) {
    std::filesystem::create_directories(dir / g);
    for (int i = 0; i < per_group; ++i) {
      char name[16];
      std::snprintf(name, sizeof name, "c%03d", i);
      write_clip(dir / g / (std::string(name) + ".json"), 2);
      ids.push_back(std::string(g) + "/" + name);
    }
  }
  return ids;
}

// `wheelpose review serve` as a child process; each start logs to a file of its own.
class ServerProcess {
 public:
  ServerProcess(const std::filesystem::path& dir, int port) : dir_(dir), port_(port) {}

  void start() {
    child_.start({"review", "serve", "--clips", (dir_ / "g1").string(), (dir_ / "g2").string(),
                  "--db", (dir_ / "review.sqlite").string(), "--port", std::to_string(port_)},
                 dir_ / ("serve" + std::to_string(starts_++) + ".log"));
  }
  void stop(int sig) { child_.stop(sig); }
  const std::string& output() const { return child_.output(); }
  int port() const { return port_; }

 private:
  std::filesystem::path dir_;
  int port_;
  int starts_ = 0;
  testing::ChildServer child_;
};

httplib::Headers auth(const std::string& token) { return {{"Authorization", "Bearer " + token}}; }

class ReviewServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fresh_temp_dir(
        "review_server_" +
        std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  }
  std::filesystem::path dir_;
};

TEST_F(ReviewServerTest, AuthorisationSeparatesParticipantsAndAdmin) {
  const auto ids = make_clips(dir_, 3);
  std::string a, b, admin;
  {
    bool created = false;
    review::ReviewStore store(dir_ / "review.sqlite", &created);
    ASSERT_TRUE(created);
    a = store.add_participant("A").token;
    b = store.add_participant("B").token;
    admin = store.admin_token();
  }
  ServerProcess server(dir_, free_port());
  server.start();
  httplib::Client c("127.0.0.1", server.port());

  // No token, a wrong token, a token of the wrong kind.
  EXPECT_EQ(c.Get("/api/session")->status, 401);
  EXPECT_EQ(c.Get("/api/session", auth(std::string(64, '0')))->status, 401);
  EXPECT_EQ(c.Get("/api/admin/status")->status, 401);
  EXPECT_EQ(c.Get("/api/admin/status", auth(a))->status, 403);
  EXPECT_EQ(c.Get("/api/session", auth(admin))->status, 403);
  EXPECT_EQ(c.Get("/api/clip?id=g1/c000")->status, 401);
  EXPECT_EQ(c.Put("/api/rating", R"({"clip":"g1/c000","q1":3})", "application/json")->status, 401);

  // A writes; B sees none of it and B's writes do not touch A's answers.
  ASSERT_EQ(c.Post("/api/consent", auth(a), R"({"consent":true})", "application/json")->status,
            200);
  ASSERT_EQ(c.Post("/api/consent", auth(b), R"({"consent":true})", "application/json")->status,
            200);
  ASSERT_EQ(c.Put("/api/rating", auth(a), R"({"clip":"g1/c000","q1":2,"q2":5,"q3":true})",
                  "application/json")
                ->status,
            200);
  ASSERT_EQ(
      c.Put("/api/rating", auth(b), R"({"clip":"g1/c000","q1":7})", "application/json")->status,
      200);
  // There is no way to name another participant: an extra field is refused.
  EXPECT_EQ(c.Put("/api/rating", auth(b), R"({"clip":"g1/c001","q1":7,"participant_id":1})",
                  "application/json")
                ->status,
            400);
  const json sa = json::parse(c.Get("/api/session", auth(a))->body);
  const json sb = json::parse(c.Get("/api/session", auth(b))->body);
  EXPECT_EQ(sa["name"], "A");
  EXPECT_EQ(sa["ratings"]["g1/c000"], json({{"q1", 2}, {"q2", 5}, {"q3", true}}));
  EXPECT_EQ(sb["name"], "B");
  EXPECT_EQ(sb["ratings"].size(), 1u);
  EXPECT_EQ(sb["ratings"]["g1/c000"], json({{"q1", 7}, {"q2", nullptr}, {"q3", nullptr}}));
  // Group order: both groups, recorded and stable across calls.
  ASSERT_EQ(sa["groups"].size(), 2u);
  EXPECT_EQ(json::parse(c.Get("/api/session", auth(a))->body)["groups"], sa["groups"]);

  // The admin sees both.
  const auto status = c.Get("/api/admin/status", auth(admin));
  ASSERT_EQ(status->status, 200);
  EXPECT_EQ(json::parse(status->body).size(), 2u);
  const auto csv = c.Get("/api/admin/export?format=csv", auth(admin));
  ASSERT_EQ(csv->status, 200);
  EXPECT_NE(csv->body.find("A,g1,g1/c000,2,5,yes,"), std::string::npos) << csv->body;
  EXPECT_NE(csv->body.find("B,g1,g1/c000,7,,,"), std::string::npos) << csv->body;
  (void)ids;
}

TEST_F(ReviewServerTest, RejectsInvalidInput) {
  make_clips(dir_, 2);
  std::string a;
  {
    review::ReviewStore store(dir_ / "review.sqlite");
    a = store.add_participant("A").token;
  }
  ServerProcess server(dir_, free_port());
  server.start();
  httplib::Client c("127.0.0.1", server.port());
  auto put = [&](const char* path, const std::string& body) {
    return c.Put(path, auth(a), body, "application/json")->status;
  };
  // Before consent, answers are refused.
  EXPECT_EQ(put("/api/rating", R"({"clip":"g1/c000","q1":3})"), 403);
  EXPECT_EQ(c.Post("/api/consent", auth(a), R"({"consent":false})", "application/json")->status,
            400);
  ASSERT_EQ(c.Post("/api/consent", auth(a), R"({"consent":true})", "application/json")->status,
            200);
  for (const char* bad :
       {R"({"clip":"g1/c000","q1":0})", R"({"clip":"g1/c000","q1":8})",
        R"({"clip":"g1/c000","q2":"3"})", R"({"clip":"g1/c000","q2":3.5})",
        R"({"clip":"g1/c000","q3":"yes"})", R"({"clip":"g1/c000","q3":1})", R"({"clip":"g1/c000"})",
        R"({"clip":"g1/nope","q1":3})", R"({"clip":"../etc/passwd","q1":3})", R"({"q1":3})",
        "not json", "[1,2]"}) {
    EXPECT_EQ(put("/api/rating", bad), 400) << bad;
  }
  EXPECT_EQ(put("/api/rating", R"({"clip":"g2/c001","q1":1,"q2":7,"q3":false})"), 200);
  EXPECT_EQ(put("/api/questionnaire", R"({"age":5})"), 400);
  EXPECT_EQ(put("/api/questionnaire", R"({"age":"40"})"), 400);
  EXPECT_EQ(put("/api/questionnaire", R"({"shoe_size":"40"})"), 400);
  EXPECT_EQ(put("/api/questionnaire", json{{"gender", std::string(501, 'x')}}.dump()), 400);
  EXPECT_EQ(put("/api/questionnaire", R"({"age":40,"level":"T-12","mobility":"full"})"), 200);
  EXPECT_EQ(put("/api/free-text", json{{"criteria", std::string(5001, 'x')}}.dump()), 400);
  // Markup is stored as text and given back as JSON data, never interpreted by the server.
  EXPECT_EQ(put("/api/free-text", R"({"criteria":"<script>alert(1)</script>"})"), 200);
  // Bodies over the limit are refused before they are parsed.
  EXPECT_EQ(put("/api/free-text", json{{"criteria", std::string(70000, 'x')}}.dump()), 413);
  EXPECT_EQ(c.Get("/api/clip?id=g1/nope", auth(a))->status, 404);
  const auto clip = c.Get("/api/clip?id=g1/c000", auth(a));
  ASSERT_EQ(clip->status, 200);
  const json payload = json::parse(clip->body);
  EXPECT_EQ(payload["frames"].size(), 2u);
  EXPECT_EQ(payload["frames"][0].size(), 3u * motion::kJointCount);
  EXPECT_EQ(payload["parents"][0], -1);

  const json s = json::parse(c.Get("/api/session", auth(a))->body);
  EXPECT_EQ(s["questionnaire"]["age"], 40);
  EXPECT_EQ(s["free_text"]["criteria"], "<script>alert(1)</script>");
  EXPECT_EQ(s["ratings"].size(), 1u);

  // The page is served with a policy that forbids inline and foreign scripts.
  const auto page = c.Get("/");
  ASSERT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("app.js"), std::string::npos);
  EXPECT_EQ(page->get_header_value("Content-Security-Policy").rfind("default-src 'self'", 0), 0u);
}

TEST_F(ReviewServerTest, LoadWithKillAndRestartLosesNoAcknowledgedAnswer) {
  constexpr int kParticipants = 50;
  constexpr int kAnswers = 200;
  const auto ids = make_clips(dir_, kAnswers / 2);
  std::vector<std::string> tokens;
  {
    review::ReviewStore store(dir_ / "review.sqlite");
    for (int p = 0; p < kParticipants; ++p) {
      tokens.push_back(store.add_participant("P" + std::to_string(p)).token);
    }
  }
  auto answer = [](int p, int i) {
    return json{{"q1", 1 + (p + i) % 7}, {"q2", 1 + (3 * p + i) % 7}, {"q3", (p + i) % 2 == 0}};
  };
  ServerProcess server(dir_, free_port());
  server.start();
  std::vector<std::atomic<int>> acked(kParticipants);
  std::atomic<int> total{0};
  std::atomic<int> retries{0};
  std::vector<std::thread> clients;
  const auto t0 = std::chrono::steady_clock::now();
  for (int p = 0; p < kParticipants; ++p) {
    clients.emplace_back([&, p] {
      httplib::Client c("127.0.0.1", server.port());
      c.set_connection_timeout(2);
      c.set_read_timeout(10);
      auto send = [&](auto request) {
        for (int attempt = 0; attempt < 400; ++attempt) {
          auto res = request();
          if (res && res->status == 200) return true;
          ++retries;
          std::this_thread::sleep_for(std::chrono::milliseconds(25));
        }
        return false;
      };
      if (!send([&] {
            return c.Post("/api/consent", auth(tokens[p]), R"({"consent":true})",
                          "application/json");
          })) {
        return;
      }
      for (int i = 0; i < kAnswers; ++i) {
        json body = answer(p, i);
        body["clip"] = ids[i];
        if (!send([&] {
              return c.Put("/api/rating", auth(tokens[p]), body.dump(), "application/json");
            })) {
          return;
        }
        acked[p] = i + 1;  // acknowledged: the server committed it before answering 200
        ++total;
      }
    });
  }
  while (total < kParticipants * kAnswers / 3)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  server.stop(SIGKILL);
  // With the server dead, everything acknowledged so far must be on disk.
  {
    std::vector<int> snapshot;
    for (auto& a : acked) snapshot.push_back(a.load());
    review::ReviewStore store(dir_ / "review.sqlite");
    std::map<std::pair<std::string, std::string>, review::Rating> stored;
    const auto participants = store.participants();
    for (const auto& r : store.ratings()) {
      stored[{participants[r.participant_id - 1].name, r.clip_id}] = r;
    }
    int checked = 0;
    for (int p = 0; p < kParticipants; ++p) {
      for (int i = 0; i < snapshot[p]; ++i) {
        auto it = stored.find({"P" + std::to_string(p), ids[i]});
        ASSERT_NE(it, stored.end()) << "lost P" << p << " " << ids[i];
        EXPECT_EQ(*it->second.q1, answer(p, i)["q1"].get<int>());
        ++checked;
      }
    }
    EXPECT_GT(checked, kParticipants * kAnswers / 3 - 1);
  }
  server.start();
  for (auto& t : clients) t.join();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  server.stop(SIGTERM);
  ASSERT_EQ(total.load(), kParticipants * kAnswers);

  review::ReviewStore store(dir_ / "review.sqlite");
  const auto ratings = store.ratings();
  ASSERT_EQ(ratings.size(), static_cast<std::size_t>(kParticipants * kAnswers));
  const auto participants = store.participants();
  std::set<std::pair<std::int64_t, std::string>> seen;
  for (const auto& r : ratings) {
    ASSERT_TRUE(seen.insert({r.participant_id, r.clip_id}).second);
    const int p = std::stoi(participants[r.participant_id - 1].name.substr(1));
    const int i = static_cast<int>(std::find(ids.begin(), ids.end(), r.clip_id) - ids.begin());
    const json expected = answer(p, i);
    ASSERT_TRUE(r.complete());
    EXPECT_EQ(*r.q1, expected["q1"].get<int>());
    EXPECT_EQ(*r.q2, expected["q2"].get<int>());
    EXPECT_EQ(*r.q3, expected["q3"].get<bool>());
  }
  std::printf("load: %d answers in %.1f s (%d retries across the restart)\n",
              kParticipants * kAnswers, seconds, retries.load());
}

TEST_F(ReviewServerTest, SlowOrMalformedClientsDoNotStallIt) {
  make_clips(dir_, 1);
  ServerProcess server(dir_, free_port());
  server.start();
  testing::expect_slow_and_malformed_clients_refused(server.port(), "/", 16);
  // Still serving afterwards.
  httplib::Client c("127.0.0.1", server.port());
  EXPECT_EQ(c.Get("/api/session")->status, 401);
}

}  // namespace
}  // namespace wheelpose
