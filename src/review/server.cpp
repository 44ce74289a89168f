#include "review/server.h"

#include <httplib.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "core/error.h"
#include "core/random.h"
#include "http/http_host.h"
#include "review/analysis.h"
#include "review/clips.h"
#include "review/store.h"

namespace wheelpose::review {
namespace {

using nlohmann::json;

// A request that fails validation or authorisation: answered with `status` and a JSON error.
struct HttpError {
  int status;
  std::string message;
};

void send_json(httplib::Response& res, const json& body, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(), "application/json; charset=utf-8");
}

std::string bearer_token(const httplib::Request& req) {
  const std::string header = req.get_header_value("Authorization");
  const std::string prefix = "Bearer ";
  if (header.compare(0, prefix.size(), prefix) != 0) return "";
  return header.substr(prefix.size());
}

json parse_object(const httplib::Request& req) {
  json body = json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) {
    throw HttpError{400, "the request body must be a JSON object"};
  }
  return body;
}

void reject_unknown_keys(const json& body, std::initializer_list<const char*> allowed) {
  for (const auto& [key, value] : body.items()) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || key == a;
    if (!ok) throw HttpError{400, "unknown field '" + key.substr(0, 40) + "'"};
  }
}

// Optional text field: absent or null → "", otherwise a string of at most `max_len` bytes.
std::string text_field(const json& body, const char* key, std::size_t max_len) {
  if (!body.contains(key) || body[key].is_null()) return "";
  if (!body[key].is_string()) throw HttpError{400, std::string(key) + " must be text"};
  std::string v = body[key].get<std::string>();
  if (v.size() > max_len) {
    throw HttpError{400,
                    std::string(key) + " is longer than " + std::to_string(max_len) + " bytes"};
  }
  return v;
}

std::optional<int> likert(const json& body, const char* key) {
  if (!body.contains(key) || body[key].is_null()) return std::nullopt;
  const json& v = body[key];
  if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 7) {
    throw HttpError{400, std::string(key) + " must be an integer from 1 to 7"};
  }
  return static_cast<int>(v.get<long long>());
}

class ReviewServer {
 public:
  ReviewServer(ReviewStore& store, const ClipCatalog& catalog)
      : store_(store), catalog_(catalog), admin_token_(store.admin_token()) {}

  void install(httplib::Server& server) {
    server.Get("/api/session", wrap([this](const auto& req, auto& res) {
                 send_json(res, session(participant(req)));
               }));
    server.Get("/api/clip", wrap([this](const auto& req, auto& res) {
                 participant(req);
                 const std::string id = req.get_param_value("id");
                 if (!catalog_.contains(id)) throw HttpError{404, "unknown clip id"};
                 res.set_header("Cache-Control", "private, max-age=3600");
                 res.set_content(catalog_.payload(id), "application/json; charset=utf-8");
               }));
    server.Post("/api/consent", wrap([this](const auto& req, auto& res) {
                  const Participant p = participant(req);
                  const json body = parse_object(req);
                  reject_unknown_keys(body, {"consent"});
                  if (!body.contains("consent") || body["consent"] != true) {
                    throw HttpError{400, "consent must be true"};
                  }
                  store_.set_consent(p.id);
                  send_json(res, {{"ok", true}});
                }));
    server.Put("/api/questionnaire", wrap([this](const auto& req, auto& res) {
                 const Participant p = consented(req);
                 const json body = parse_object(req);
                 reject_unknown_keys(body, {"age", "gender", "occupation", "condition", "level",
                                            "exercise", "mobility"});
                 json clean = json::object();
                 if (body.contains("age") && !body["age"].is_null()) {
                   const json& age = body["age"];
                   if (!age.is_number_integer() || age.get<long long>() < 18 ||
                       age.get<long long>() > 120) {
                     throw HttpError{400, "age must be a whole number from 18 to 120"};
                   }
                   clean["age"] = age.get<long long>();
                 } else {
                   clean["age"] = nullptr;
                 }
                 for (const char* key :
                      {"gender", "occupation", "condition", "level", "exercise", "mobility"}) {
                   clean[key] = text_field(body, key, 500);
                 }
                 store_.set_questionnaire(p.id, clean.dump());
                 send_json(res, {{"ok", true}});
               }));
    server.Put("/api/rating", wrap([this](const auto& req, auto& res) {
                 const Participant p = consented(req);
                 const json body = parse_object(req);
                 reject_unknown_keys(body, {"clip", "q1", "q2", "q3"});
                 if (!body.contains("clip") || !body["clip"].is_string() ||
                     !catalog_.contains(body["clip"].get<std::string>())) {
                   throw HttpError{400, "clip must be the id of a clip in this study"};
                 }
                 Rating r;
                 r.participant_id = p.id;
                 r.clip_id = body["clip"].get<std::string>();
                 r.q1 = likert(body, "q1");
                 r.q2 = likert(body, "q2");
                 if (body.contains("q3") && !body["q3"].is_null()) {
                   if (!body["q3"].is_boolean()) throw HttpError{400, "q3 must be true or false"};
                   r.q3 = body["q3"].get<bool>();
                 }
                 if (!r.q1 && !r.q2 && !r.q3)
                   throw HttpError{400, "give at least one of q1, q2, q3"};
                 store_.save_rating(r);
                 send_json(res, {{"ok", true}});
               }));
    server.Put("/api/free-text", wrap([this](const auto& req, auto& res) {
                 const Participant p = consented(req);
                 const json body = parse_object(req);
                 reject_unknown_keys(body, {"criteria", "frequency", "missing"});
                 json clean = json::object();
                 for (const char* key : {"criteria", "frequency", "missing"}) {
                   clean[key] = text_field(body, key, 5000);
                 }
                 store_.set_free_text(p.id, clean.dump());
                 send_json(res, {{"ok", true}});
               }));
    server.Post("/api/finish", wrap([this](const auto& req, auto& res) {
                  const Participant p = consented(req);
                  store_.set_finished(p.id);
                  send_json(res, {{"ok", true}});
                }));
    server.Get("/api/admin/status", wrap([this](const auto& req, auto& res) {
                 admin(req);
                 send_json(res, status_json(store_));
               }));
    server.Get("/api/admin/export", wrap([this](const auto& req, auto& res) {
                 admin(req);
                 const std::string format =
                     req.has_param("format") ? req.get_param_value("format") : std::string("json");
                 if (format == "csv") {
                   res.set_header("Cache-Control", "no-store");
                   res.set_content(export_csv(store_), "text/csv; charset=utf-8");
                 } else if (format == "json") {
                   send_json(res, export_json(store_));
                 } else {
                   throw HttpError{400, "format must be csv or json"};
                 }
               }));
  }

 private:
  template <typename F>
  httplib::Server::Handler wrap(F f) {
    return [f](const httplib::Request& req, httplib::Response& res) {
      try {
        f(req, res);
      } catch (const HttpError& e) {
        if (e.status == 401) res.set_header("WWW-Authenticate", "Bearer");
        send_json(res, {{"error", e.message}}, e.status);
      } catch (const Error& e) {
        spdlog::error("{} {}: {}", req.method, req.path, e.what());
        send_json(res, {{"error", "the server could not store this; please try again"}}, 500);
      }
    };
  }

  Participant participant(const httplib::Request& req) {
    const std::string token = bearer_token(req);
    if (token.empty()) throw HttpError{401, "missing access token"};
    if (auto p = store_.participant_by_token(token)) return *p;
    if (constant_time_equal(token, admin_token_)) {
      throw HttpError{403, "the admin token has no participant data"};
    }
    throw HttpError{401, "unknown access token"};
  }

  Participant consented(const httplib::Request& req) {
    Participant p = participant(req);
    if (p.consent_at.empty()) throw HttpError{403, "consent has not been given"};
    return p;
  }

  void admin(const httplib::Request& req) {
    const std::string token = bearer_token(req);
    if (token.empty()) throw HttpError{401, "missing access token"};
    if (constant_time_equal(token, admin_token_)) return;
    if (store_.participant_by_token(token)) throw HttpError{403, "admin only"};
    throw HttpError{401, "unknown access token"};
  }

  // Group order: a seeded shuffle per participant, recorded the first time so it never changes.
  std::vector<std::string> group_order(const Participant& p) {
    if (!p.group_order.empty()) return p.group_order;
    std::vector<std::string> order;
    for (const auto& g : catalog_.groups()) order.push_back(g.name);
    RandomStream rng(store_.study_seed(), {"group_order", static_cast<std::uint64_t>(p.id)});
    for (std::size_t i = order.size(); i > 1; --i) {
      const auto j = static_cast<std::size_t>(rng.uniform_int(0, static_cast<std::int64_t>(i) - 1));
      std::swap(order[i - 1], order[j]);
    }
    return store_.assign_group_order(p.id, order);
  }

  json session(const Participant& p) {
    json groups = json::array();
    for (const auto& name : group_order(p)) {
      for (const auto& g : catalog_.groups()) {
        if (g.name == name) groups.push_back({{"name", g.name}, {"clips", g.clip_ids}});
      }
    }
    // Groups present now but not when the order was recorded go last, in folder order.
    for (const auto& g : catalog_.groups()) {
      bool listed = false;
      for (const auto& e : groups) listed = listed || e["name"] == g.name;
      if (!listed) groups.push_back({{"name", g.name}, {"clips", g.clip_ids}});
    }
    json ratings = json::object();
    for (const auto& r : store_.ratings(p.id)) {
      if (!catalog_.contains(r.clip_id)) continue;
      ratings[r.clip_id] = {{"q1", r.q1 ? json(*r.q1) : json(nullptr)},
                            {"q2", r.q2 ? json(*r.q2) : json(nullptr)},
                            {"q3", r.q3 ? json(*r.q3) : json(nullptr)}};
    }
    const std::string q = store_.questionnaire(p.id);
    const std::string f = store_.free_text(p.id);
    return {{"name", p.name},
            {"consent", !p.consent_at.empty()},
            {"questionnaire", q.empty() ? json(nullptr) : json::parse(q)},
            {"free_text", f.empty() ? json(nullptr) : json::parse(f)},
            {"finished", !p.finished_at.empty()},
            {"groups", groups},
            {"ratings", ratings}};
  }

  ReviewStore& store_;
  const ClipCatalog& catalog_;
  std::string admin_token_;
};

}  // namespace

std::string participant_link(const std::string& base_url, const std::string& token) {
  std::string base = base_url;
  while (!base.empty() && base.back() == '/') base.pop_back();
  return base + "/#token=" + token;
}

void serve(const ServeOptions& options) {
  // Block the stop signals in every thread; one thread waits for them and stops the server.
  const sigset_t signals = http::block_stop_signals();

  const ClipCatalog catalog(options.clip_folders);
  bool created = false;
  ReviewStore store(options.db, &created);
  store.register_clips(catalog.records());

  std::filesystem::path web = options.web_dir.empty()
                                  ? std::filesystem::path(WHEELPOSE_SOURCE_DIR) / "web" / "review"
                                  : options.web_dir;
  if (!std::filesystem::is_regular_file(web / "index.html")) {
    throw Error(web.string() +
                ": no index.html (give --web DIR, the repository's web/review folder)");
  }

  httplib::Server server;
  // Enough workers that a study's participants never queue behind each other (SQLite writes are
  // serialised anyway), and short read timeouts so silent clients do not hold them.
  http::set_connection_limits(server, kMaxRequestBytes);
  http::set_security_headers(server);
  ReviewServer api(store, catalog);
  api.install(server);
  if (!server.set_mount_point("/", web.string())) {
    throw Error(web.string() + ": cannot serve this folder", ErrorKind::kFailure);
  }
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) {
      res.set_content(json{{"error", "HTTP " + std::to_string(res.status)}}.dump(),
                      "application/json; charset=utf-8");
    }
  });

  const std::string url = http::bind_server(server, options.bind, options.port);
  if (created) std::printf("admin token (shown once, keep it): %s\n", store.admin_token().c_str());
  std::printf("serving %zu clips in %zu groups from %s\nlistening on %s\n", catalog.size(),
              catalog.groups().size(), options.db.c_str(), url.c_str());
  std::fflush(stdout);

  http::listen_until_signal(server, signals);
}

}  // namespace wheelpose::review
