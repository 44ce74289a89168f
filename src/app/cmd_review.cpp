// `wheelpose review`: wheelchair users rate motions in the browser (paper "Human Evaluation");
// the ratings then filter the clips the generator uses.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "review/analysis.h"
#include "review/report.h"
#include "review/server.h"
#include "review/store.h"

namespace wheelpose::app {
namespace {

// "10%" or "10" → 10.0; throws Error naming the flag otherwise.
double parse_percent(const std::string& text) {
  std::string number = text;
  if (!number.empty() && number.back() == '%') number.pop_back();
  std::size_t used = 0;
  double value = NAN;
  try {
    value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size() || !std::isfinite(value)) {
    throw Error("--drop-bottom: expected a percentage such as 10%, got '" + text + "'");
  }
  return value;
}

std::unique_ptr<review::ReviewStore> open_existing(const std::string& db) {
  if (!std::filesystem::is_regular_file(db)) {
    throw Error(db +
                ": no such review database (it is created by `review serve` or `review invite`)");
  }
  return std::make_unique<review::ReviewStore>(db);
}

void attach_serve(CLI::App& review) {
  auto o = std::make_shared<review::ServeOptions>();
  auto folders = std::make_shared<std::vector<std::string>>();
  auto db = std::make_shared<std::string>();
  auto web = std::make_shared<std::string>();
  auto* c = review.add_subcommand("serve", "Run the rating web app (Ctrl-C stops it)");
  c->add_option("--clips", *folders, "Folders of seated-clip JSON files; each folder is one group")
      ->required()
      ->expected(1, -1);
  c->add_option("--db", *db, "SQLite database (created if missing)")->required();
  c->add_option("--port", o->port, "TCP port (0 picks a free one)")->check(CLI::Range(0, 65535));
  c->add_option("--bind", o->bind, "Address to listen on (default: this machine only)");
  c->add_option("--web", *web, "Folder of the page (default: the source tree's web/review)");
  c->callback([o, folders, db, web] {
    for (const auto& f : *folders) o->clip_folders.emplace_back(f);
    o->db = *db;
    o->web_dir = *web;
    review::serve(*o);
  });
}

void attach_invite(CLI::App& review) {
  auto db = std::make_shared<std::string>();
  auto name = std::make_shared<std::string>();
  auto url = std::make_shared<std::string>("http://127.0.0.1:8080");
  auto* c = review.add_subcommand("invite", "Add a participant and print their personal link");
  c->add_option("--db", *db, "SQLite database (created if missing)")->required();
  c->add_option("--name", *name, "Participant label, e.g. P1 (no real names needed)")->required();
  c->add_option("--url", *url, "Address participants reach the server at");
  c->callback([db, name, url] {
    bool created = false;
    review::ReviewStore store(*db, &created);
    if (created)
      std::printf("admin token (shown once, keep it): %s\n", store.admin_token().c_str());
    const review::Participant p = store.add_participant(*name);
    std::printf("%s: %s\n", p.name.c_str(), review::participant_link(*url, p.token).c_str());
  });
}

void attach_status(CLI::App& review) {
  auto db = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* c = review.add_subcommand("status", "Progress of every participant");
  c->add_option("--db", *db, "SQLite database")->required();
  c->add_flag("--json", *json, "Print JSON instead of a table");
  c->callback([db, json] {
    auto store = open_existing(*db);
    if (*json) {
      std::printf("%s\n", review::status_json(*store).dump(2).c_str());
    } else {
      std::fputs(review::status_text(*store).c_str(), stdout);
    }
  });
}

void attach_export(CLI::App& review) {
  auto db = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>("csv");
  auto out = std::make_shared<std::string>();
  auto* c = review.add_subcommand("export", "All answers as CSV (ratings) or JSON (everything)");
  c->add_option("--db", *db, "SQLite database")->required();
  c->add_option("--format", *format, "csv or json")->check(CLI::IsMember({"csv", "json"}));
  c->add_option("--out", *out, "Output file (default: standard output)");
  c->callback([db, format, out] {
    auto store = open_existing(*db);
    const std::string text =
        *format == "csv" ? review::export_csv(*store) : review::export_json(*store).dump(2) + "\n";
    if (out->empty()) {
      std::fputs(text.c_str(), stdout);
    } else {
      write_file_atomic(*out, text);
    }
  });
}

void attach_report(CLI::App& review) {
  auto db = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto* c = review.add_subcommand("report", "HTML + PNG figures of the ratings and the ranking");
  c->add_option("--db", *db, "SQLite database")->required();
  c->add_option("--out", *out, "Output folder")->required();
  c->callback([db, out] {
    auto store = open_existing(*db);
    const auto files = review::write_report(*store, *out);
    std::printf("wrote %zu files, open %s\n", files.size(), files.back().c_str());
  });
}

void attach_filter(CLI::App& review) {
  auto db = std::make_shared<std::string>();
  auto drop = std::make_shared<std::string>("10%");
  auto out = std::make_shared<std::string>();
  auto groups = std::make_shared<std::vector<std::string>>();
  auto* c = review.add_subcommand(
      "filter", "Drop the lowest-rated clips; write ranking.json for `generate --clips-from`");
  c->add_option("--db", *db, "SQLite database")->required();
  c->add_option("--drop-bottom", *drop, "Share of rated clips to drop, e.g. 10%");
  c->add_option("--group", *groups, "Only drop clips of these groups (repeatable)");
  c->add_option("--out", *out, "ranking.json to write")->required();
  c->callback([db, drop, out, groups] {
    const double percent = parse_percent(*drop);
    auto store = open_existing(*db);
    const auto doc = review::filter_ranking(*store, percent, *groups);
    write_file_atomic(*out, doc.dump(2) + "\n");
    std::printf("kept %zu clips, dropped %zu; wrote %s\n", doc["kept"].size(),
                doc["dropped"].size(), out->c_str());
  });
}

}  // namespace

void attach_review(CLI::App& parent) {
  auto* review = parent.add_subcommand(
      "review", "Human evaluation: wheelchair users rate clips in the browser");
  review->require_subcommand(1);
  attach_serve(*review);
  attach_invite(*review);
  attach_status(*review);
  attach_export(*review);
  attach_report(*review);
  attach_filter(*review);
}

}  // namespace wheelpose::app
