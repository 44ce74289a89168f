#pragma once
// Text placed in HTML reports (stats, review analysis): the one escaping rule they share.

#include <string>

namespace wheelpose {

// Escapes & < > " and ' so the text is safe in element content and in quoted attributes.
std::string html_escape(const std::string& text);

}  // namespace wheelpose
