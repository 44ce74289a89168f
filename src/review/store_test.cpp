#include "review/store.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace wheelpose::review {
namespace {

std::filesystem::path fresh_db(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("wheelpose_store_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir / "review.sqlite";
}

TEST(ReviewStore, CreatesOnceAndKeepsItsSecretsAcrossReopening) {
  const auto path = fresh_db("reopen");
  bool created = false;
  std::string token;
  std::uint64_t seed = 0;
  {
    ReviewStore store(path, &created);
    EXPECT_TRUE(created);
    token = store.admin_token();
    seed = store.study_seed();
    EXPECT_EQ(token.size(), 64u);
  }
  ReviewStore again(path, &created);
  EXPECT_FALSE(created);
  EXPECT_EQ(again.admin_token(), token);
  EXPECT_EQ(again.study_seed(), seed);
}

TEST(ReviewStore, RefusesAFileThatIsNotADatabase) {
  const auto path = fresh_db("not_a_db");
  std::ofstream(path) << "these are not the bytes of an SQLite file, just some text";
  EXPECT_THROW(ReviewStore store(path), Error);
}

TEST(ReviewStore, ParticipantsAreUniqueAndFoundByNameAndToken) {
  ReviewStore store(fresh_db("participants"));
  const Participant ana = store.add_participant("ana");
  const Participant ben = store.add_participant("ben");
  EXPECT_NE(ana.id, ben.id);
  EXPECT_NE(ana.token, ben.token);
  EXPECT_THROW(store.add_participant("ana"), Error);
  EXPECT_THROW(store.add_participant(""), Error);
  EXPECT_THROW(store.add_participant(std::string(101, 'x')), Error);
  ASSERT_EQ(store.participants().size(), 2u);
  EXPECT_EQ(store.participant_by_name("ben")->id, ben.id);
  EXPECT_FALSE(store.participant_by_name("cyd"));
  EXPECT_EQ(store.participant_by_token(ana.token)->name, "ana");
  EXPECT_FALSE(store.participant_by_token(std::string(64, '0')));
}

TEST(ReviewStore, ConsentFinishAndGroupOrderAreRecordedOnce) {
  ReviewStore store(fresh_db("once"));
  const Participant p = store.add_participant("ana");
  EXPECT_TRUE(store.participant_by_name("ana")->consent_at.empty());
  store.set_consent(p.id);
  const std::string consent = store.participant_by_name("ana")->consent_at;
  EXPECT_FALSE(consent.empty());
  store.set_consent(p.id);  // a second consent keeps the first time
  EXPECT_EQ(store.participant_by_name("ana")->consent_at, consent);

  EXPECT_EQ(store.assign_group_order(p.id, {"b", "a"}), (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(store.assign_group_order(p.id, {"a", "b"}), (std::vector<std::string>{"b", "a"}));
  EXPECT_EQ(store.participant_by_name("ana")->group_order, (std::vector<std::string>{"b", "a"}));
  EXPECT_THROW(store.assign_group_order(p.id + 100, {"a"}), Error);

  store.set_finished(p.id);
  EXPECT_FALSE(store.participant_by_name("ana")->finished_at.empty());
}

TEST(ReviewStore, RegisteringClipsReplacesTheListInGroupOrder) {
  ReviewStore store(fresh_db("clips"));
  store.register_clips({{"old/x", "old", 0, "/x.json"}});
  store.register_clips(
      {{"h/b", "h", 1, "/h/b.json"}, {"g/a", "g", 0, "/g/a.json"}, {"h/a", "h", 0, "/h/a.json"}});
  const std::vector<ClipRecord> clips = store.clips();
  ASSERT_EQ(clips.size(), 3u);
  EXPECT_EQ(clips[0].id, "g/a");
  EXPECT_EQ(clips[1].id, "h/a");
  EXPECT_EQ(clips[2].id, "h/b");
  EXPECT_EQ(clips[2].path, "/h/b.json");
}

TEST(ReviewStore, AnswersAreReplacedPerParticipantAndKeptApart) {
  ReviewStore store(fresh_db("answers"));
  const Participant ana = store.add_participant("ana");
  const Participant ben = store.add_participant("ben");
  EXPECT_EQ(store.questionnaire(ana.id), "");
  store.set_questionnaire(ana.id, R"({"age":30})");
  store.set_questionnaire(ana.id, R"({"age":31})");
  store.set_free_text(ana.id, R"({"note":"hi"})");
  store.set_questionnaire(ben.id, R"({"age":40})");
  EXPECT_EQ(store.questionnaire(ana.id), R"({"age":31})");
  EXPECT_EQ(store.free_text(ana.id), R"({"note":"hi"})");
  EXPECT_EQ(store.questionnaire(ben.id), R"({"age":40})");
  EXPECT_EQ(store.free_text(ben.id), "");
}

TEST(ReviewStore, ARatingSavedInPartsKeepsEveryAnswerGiven) {
  ReviewStore store(fresh_db("ratings"));
  const Participant ana = store.add_participant("ana");
  const Participant ben = store.add_participant("ben");
  Rating first{ana.id, "g/a", 5, std::nullopt, std::nullopt, ""};
  store.save_rating(first);
  Rating second{ana.id, "g/a", std::nullopt, 3, false, ""};
  store.save_rating(second);
  store.save_rating({ben.id, "g/a", 1, 1, true, ""});
  store.save_rating({ana.id, "g/b", 2, std::nullopt, std::nullopt, ""});

  const std::vector<Rating> mine = store.ratings(ana.id);
  ASSERT_EQ(mine.size(), 2u);
  EXPECT_EQ(mine[0].clip_id, "g/a");
  EXPECT_EQ(mine[0].q1, 5);
  EXPECT_EQ(mine[0].q2, 3);
  EXPECT_EQ(mine[0].q3, false);
  EXPECT_TRUE(mine[0].complete());
  EXPECT_FALSE(mine[1].complete());
  EXPECT_FALSE(mine[1].q2);
  EXPECT_EQ(store.ratings().size(), 3u);
}

}  // namespace
}  // namespace wheelpose::review
