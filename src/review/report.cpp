#include "review/report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/html.h"
#include "review/analysis.h"

namespace wheelpose::review {
namespace {

// --- figures -------------------------------------------------------------------------------

// Likert 1..7 from red (1) to green (7), BGR.
cv::Scalar likert_colour(int v) {
  static const cv::Scalar colours[7] = {{43, 57, 192},   {60, 110, 230},  {90, 170, 245},
                                        {190, 190, 190}, {150, 200, 140}, {90, 160, 60},
                                        {40, 110, 30}};
  return colours[std::clamp(v, 1, 7) - 1];
}

void put_text(cv::Mat& img, const std::string& text, cv::Point at, double scale = 0.5,
              int thickness = 1) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(20, 20, 20), thickness,
              cv::LINE_AA);
}

void write_png(const std::filesystem::path& path, const cv::Mat& img) {
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", img, bytes)) {
    throw Error(path.string() + ": PNG encoding failed", ErrorKind::kFailure);
  }
  write_file_atomic(path, std::span<const std::uint8_t>(bytes));
}

// One 100 % stacked bar per participant; `counts[p][k]` is the number of answers in category k.
cv::Mat stacked_bars(const std::string& title, const std::vector<std::string>& participants,
                     const std::vector<std::vector<int>>& counts,
                     const std::vector<cv::Scalar>& colours,
                     const std::vector<std::string>& legend) {
  const int bar_w = 40, gap = 16, left = 60, top = 50, plot_h = 300;
  const int width =
      std::max(480, left + static_cast<int>(participants.size()) * (bar_w + gap) + 140);
  cv::Mat img(top + plot_h + 60, width, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(img, title, {10, 25}, 0.6, 2);
  for (int pct = 0; pct <= 100; pct += 25) {
    const int y = top + plot_h - plot_h * pct / 100;
    cv::line(img, {left - 5, y}, {left + static_cast<int>(participants.size()) * (bar_w + gap), y},
             cv::Scalar(220, 220, 220));
    put_text(img, std::to_string(pct) + "%", {10, y + 5}, 0.4);
  }
  for (std::size_t p = 0; p < participants.size(); ++p) {
    const int x = left + static_cast<int>(p) * (bar_w + gap);
    int total = 0;
    for (int c : counts[p]) total += c;
    double acc = 0.0;
    for (std::size_t k = 0; k < counts[p].size() && total > 0; ++k) {
      const double frac = static_cast<double>(counts[p][k]) / total;
      const int y0 = top + plot_h - static_cast<int>(std::lround(acc * plot_h));
      acc += frac;
      const int y1 = top + plot_h - static_cast<int>(std::lround(acc * plot_h));
      if (y0 > y1) cv::rectangle(img, {x, y1}, {x + bar_w, y0}, colours[k], cv::FILLED);
    }
    put_text(img, participants[p].substr(0, 6), {x, top + plot_h + 20}, 0.4);
  }
  const int lx = width - 120;
  for (std::size_t k = 0; k < legend.size(); ++k) {
    const int y = top + static_cast<int>(k) * 22;
    cv::rectangle(img, {lx, y}, {lx + 16, y + 16}, colours[k], cv::FILLED);
    put_text(img, legend[k], {lx + 22, y + 13}, 0.45);
  }
  return img;
}

cv::Mat scatter(const std::string& title, const std::map<std::pair<int, int>, int>& counts) {
  const int left = 60, top = 50, size = 360;
  cv::Mat img(top + size + 60, left + size + 30, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(img, title, {10, 25}, 0.55, 2);
  auto px = [&](int ease) { return left + (ease - 1) * size / 6; };
  auto py = [&](int freq) { return top + size - (freq - 1) * size / 6; };
  for (int v = 1; v <= 7; ++v) {
    cv::line(img, {px(v), top}, {px(v), top + size}, cv::Scalar(225, 225, 225));
    cv::line(img, {left, py(v)}, {left + size, py(v)}, cv::Scalar(225, 225, 225));
    put_text(img, std::to_string(v), {px(v) - 4, top + size + 20}, 0.45);
    put_text(img, std::to_string(v), {left - 20, py(v) + 5}, 0.45);
  }
  put_text(img, "ease (Q1)", {left + size / 2 - 40, top + size + 45}, 0.5);
  put_text(img, "freq", {5, top - 10}, 0.5);
  int max_count = 1;
  for (const auto& [k, c] : counts) max_count = std::max(max_count, c);
  // Answers are integers, so points coincide: the area of each circle shows how many.
  for (const auto& [k, c] : counts) {
    const int r = 3 + static_cast<int>(std::lround(18.0 * std::sqrt(double(c) / max_count)));
    cv::circle(img, {px(k.first), py(k.second)}, r, cv::Scalar(180, 110, 30), cv::FILLED,
               cv::LINE_AA);
  }
  return img;
}

}  // namespace

std::vector<std::filesystem::path> write_report(const ReviewStore& store,
                                                const std::filesystem::path& out_dir) {
  ensure_directory(out_dir);
  const auto participants = store.participants();
  const auto ratings = store.ratings();
  std::vector<std::string> names;
  for (const auto& p : participants) names.push_back(p.name);
  std::vector<cv::Scalar> likert_colours;
  std::vector<std::string> likert_legend;
  for (int v = 1; v <= 7; ++v) {
    likert_colours.push_back(likert_colour(v));
    likert_legend.push_back(std::to_string(v));
  }
  likert_legend.front() += " (low)";
  likert_legend.back() += " (high)";

  std::vector<std::filesystem::path> written;
  std::ostringstream html;
  html << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>WheelPose "
          "review report</title><style>body{font-family:sans-serif;max-width:70em;margin:auto;"
          "padding:1em}table{border-collapse:collapse}td,th{border:1px solid #999;padding:"
          "0.2em 0.5em}img{max-width:100%}</style></head><body>\n<h1>WheelPose review report</h1>\n"
       << "<p>" << participants.size() << " participants, " << ratings.size()
       << " rated clips (rows).</p>\n";
  const std::vector<GroupAnswers> answers = group_answers(store);
  for (std::size_t gi = 0; gi < answers.size(); ++gi) {
    const GroupAnswers& a = answers[gi];
    const std::string& g = a.group;
    const std::string tag = "group" + std::to_string(gi + 1);
    const std::vector<double>& xs = a.ease_values;
    const auto r = pearson(a.ease_values, a.frequency_values);
    const std::string r_text = r ? "r = " + format_number(*r) : "r undefined";
    const std::vector<std::pair<std::string, cv::Mat>> figures = {
        {tag + "_ease.png",
         stacked_bars("Ease (Q1), " + g, names, a.ease, likert_colours, likert_legend)},
        {tag + "_frequency.png",
         stacked_bars("Frequency (Q2), " + g, names, a.frequency, likert_colours, likert_legend)},
        {tag + "_scatter.png", scatter("Ease vs frequency, " + g + ": " + r_text +
                                           " (n=" + std::to_string(xs.size()) + ")",
                                       a.pairs)},
        {tag + "_seen.png",
         stacked_bars("Seen others do it (Q3), " + g, names, a.seen,
                      {cv::Scalar(90, 160, 60), cv::Scalar(60, 110, 230)}, {"yes", "no"})},
    };
    html << "<h2>Group " << html_escape(g) << "</h2>\n<p>Pearson correlation of ease and "
         << "frequency over " << xs.size() << " answers: " << html_escape(r_text) << "</p>\n";
    for (const auto& [file, img] : figures) {
      write_png(out_dir / file, img);
      written.push_back(out_dir / file);
      html << "<img src=\"" << file << "\" alt=\"" << html_escape(file) << "\">\n";
    }
  }
  html << "<h2>Ranking (mean ease + mean frequency)</h2>\n<table><tr><th>#</th><th>clip</th>"
          "<th>group</th><th>ratings</th><th>mean ease</th><th>mean frequency</th><th>score</th>"
          "<th>seen (yes)</th></tr>\n";
  int rank = 0;
  for (const auto& s : score_clips(store)) {
    html << "<tr><td>" << ++rank << "</td><td>" << html_escape(s.id) << "</td><td>"
         << html_escape(s.group) << "</td><td>" << s.ratings << "</td>";
    if (s.ratings > 0) {
      html << "<td>" << format_number(s.mean_ease, 2) << "</td><td>"
           << format_number(s.mean_frequency, 2) << "</td><td>" << format_number(s.score, 2)
           << "</td>";
    } else {
      html << "<td></td><td></td><td></td>";
    }
    html << "<td>" << s.q3_yes << "/" << s.q3_answers << "</td></tr>\n";
  }
  html << "</table>\n</body></html>\n";
  write_file_atomic(out_dir / "report.html", html.str());
  written.push_back(out_dir / "report.html");
  return written;
}

}  // namespace wheelpose::review
