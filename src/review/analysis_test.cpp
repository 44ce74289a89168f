#include "review/analysis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/error.h"
#include "review/report.h"

namespace wheelpose::review {
namespace {

std::filesystem::path temp_db(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("wheelpose_review_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// P1 rates g/a..g/e with (ease, frequency) = (1,2) (2,4) (3,5) (4,4) (5,5): by hand,
// mean (3, 4), Sxy = 6, Sxx = 10, Syy = 6, so r = 6 / sqrt(60) = 0.7745967.
// h/x is registered but never rated; the clip id with markup checks escaping.
void seed(ReviewStore& store) {
  store.register_clips({{"g/a", "g", 0, "/clips/g/a.json"},
                        {"g/b", "g", 1, "/clips/g/b.json"},
                        {"g/c", "g", 2, "/clips/g/c.json"},
                        {"g/d", "g", 3, "/clips/g/d.json"},
                        {"g/e", "g", 4, "/clips/g/e.json"},
                        {"h/<script>x</script>", "h", 0, "/clips/h/x.json"}});
  const Participant p = store.add_participant("P1");
  store.add_participant("P2, \"quoted\"");
  const int pairs[5][2] = {{1, 2}, {2, 4}, {3, 5}, {4, 4}, {5, 5}};
  const char* ids[5] = {"g/a", "g/b", "g/c", "g/d", "g/e"};
  for (int i = 0; i < 5; ++i) {
    Rating r;
    r.participant_id = p.id;
    r.clip_id = ids[i];
    r.q1 = pairs[i][0];
    store.save_rating(r);  // answers arrive one at a time
    r.q1.reset();
    r.q2 = pairs[i][1];
    r.q3 = i != 0;
    store.save_rating(r);
  }
}

TEST(ReviewAnalysis, PearsonMatchesHandComputedValue) {
  const auto r = pearson({1, 2, 3, 4, 5}, {2, 4, 5, 4, 5});
  ASSERT_TRUE(r);
  EXPECT_NEAR(*r, 6.0 / std::sqrt(60.0), 1e-12);
  EXPECT_NEAR(*pearson({1, 2, 3}, {3, 2, 1}), -1.0, 1e-12);
  EXPECT_FALSE(pearson({1, 1, 1}, {1, 2, 3}));
  EXPECT_FALSE(pearson({1}, {1}));
}

TEST(ReviewAnalysis, PartialAnswersMergeAndScoresRank) {
  const auto dir = temp_db("scores");
  ReviewStore store(dir / "db.sqlite");
  seed(store);
  const auto ratings = store.ratings();
  ASSERT_EQ(ratings.size(), 5u);
  EXPECT_TRUE(ratings[0].complete());
  EXPECT_EQ(*ratings[0].q1, 1);
  EXPECT_EQ(*ratings[0].q2, 2);
  const auto scores = score_clips(store);
  ASSERT_EQ(scores.size(), 6u);
  EXPECT_EQ(scores[0].id, "g/e");
  EXPECT_DOUBLE_EQ(scores[0].score, 10.0);
  EXPECT_EQ(scores[1].id, "g/c");  // ties (8) keep id order
  EXPECT_EQ(scores[2].id, "g/d");
  EXPECT_EQ(scores.back().ratings, 0);
}

TEST(ReviewAnalysis, FilterDropsTheBottomShareOfRatedClips) {
  const auto dir = temp_db("filter");
  ReviewStore store(dir / "db.sqlite");
  seed(store);
  // 40 % of the 5 rated clips = 2: g/a (score 3) and g/b (6).
  const auto doc = filter_ranking(store, 40.0, {});
  EXPECT_EQ(doc["format"], "wheelpose.review_ranking");
  ASSERT_EQ(doc["dropped"].size(), 2u);
  EXPECT_EQ(doc["dropped"][0]["id"], "g/b");
  EXPECT_EQ(doc["dropped"][1]["id"], "g/a");
  ASSERT_EQ(doc["kept"].size(), 4u);
  EXPECT_EQ(doc["kept"][0]["id"], "g/e");
  EXPECT_EQ(doc["kept"][0]["path"], "/clips/g/e.json");
  EXPECT_DOUBLE_EQ(doc["kept"][0]["mean_ease"].get<double>(), 5.0);
  EXPECT_TRUE(doc["kept"][3]["score"].is_null());  // unrated clips are kept, last
  // 10 % of 5 rounds down to none.
  EXPECT_EQ(filter_ranking(store, 10.0, {})["dropped"].size(), 0u);
  // Restricting to a group without ratings drops nothing; unknown groups are an error.
  EXPECT_EQ(filter_ranking(store, 50.0, {"h"})["dropped"].size(), 0u);
  EXPECT_THROW(filter_ranking(store, 50.0, {"nope"}), Error);
  EXPECT_THROW(filter_ranking(store, 100.0, {}), Error);
  EXPECT_THROW(filter_ranking(store, -1.0, {}), Error);
}

TEST(ReviewAnalysis, ReportShowsPearsonAndEscapesNames) {
  const auto dir = temp_db("report");
  ReviewStore store(dir / "db.sqlite");
  seed(store);
  const auto files = write_report(store, dir / "report");
  EXPECT_EQ(files.size(), 9u);  // 4 figures per group + report.html
  for (const auto& f : files) EXPECT_GT(std::filesystem::file_size(f), 100u) << f;
  const std::string html = read_file(dir / "report" / "report.html");
  EXPECT_NE(html.find("r = 0.775"), std::string::npos);
  EXPECT_EQ(html.find("<script>"), std::string::npos);
  EXPECT_NE(html.find("h/&lt;script&gt;x&lt;/script&gt;"), std::string::npos);
}

TEST(ReviewAnalysis, ExportQuotesCsvAndStatusCountsCompleteAnswers) {
  const auto dir = temp_db("export");
  ReviewStore store(dir / "db.sqlite");
  seed(store);
  const std::string csv = export_csv(store);
  EXPECT_EQ(csv.rfind("participant,group,clip,q1,q2,q3,updated_at\r\nP1,g,g/a,1,2,no,", 0), 0u)
      << csv;
  const auto status = status_json(store);
  ASSERT_EQ(status.size(), 2u);
  EXPECT_EQ(status[0]["answered"], 5);
  EXPECT_EQ(status[1]["name"], "P2, \"quoted\"");
  EXPECT_EQ(status[1]["answered"], 0);
}

TEST(ReviewStore, TokensAreRandomAndComparedWhole) {
  const auto dir = temp_db("tokens");
  bool created = false;
  ReviewStore store(dir / "db.sqlite", &created);
  EXPECT_TRUE(created);
  const auto a = store.add_participant("A");
  const auto b = store.add_participant("B");
  EXPECT_EQ(a.token.size(), 64u);
  EXPECT_NE(a.token, b.token);
  EXPECT_EQ(store.participant_by_token(b.token)->name, "B");
  EXPECT_FALSE(store.participant_by_token(b.token.substr(0, 63)));
  EXPECT_FALSE(store.participant_by_token(""));
  EXPECT_THROW(store.add_participant("A"), Error);
  EXPECT_TRUE(constant_time_equal("abc", "abc"));
  EXPECT_FALSE(constant_time_equal("abc", "abd"));
  EXPECT_FALSE(constant_time_equal("abc", "abcd"));
  // Reopening keeps the admin token and reports no creation.
  const std::string admin = store.admin_token();
  ReviewStore again(dir / "db.sqlite", &created);
  EXPECT_FALSE(created);
  EXPECT_EQ(again.admin_token(), admin);
  // The group order is recorded once.
  EXPECT_EQ(store.assign_group_order(a.id, {"x", "y"}), (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(store.assign_group_order(a.id, {"y", "x"}), (std::vector<std::string>{"x", "y"}));
}

}  // namespace
}  // namespace wheelpose::review
