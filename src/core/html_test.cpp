#include "core/html.h"

#include <gtest/gtest.h>

namespace wheelpose {
namespace {

TEST(HtmlEscape, EscapesTheFiveSpecialCharactersOnly) {
  EXPECT_EQ(html_escape(R"(a<b>&"c'd é)"), "a&lt;b&gt;&amp;&quot;c&#39;d é");
  EXPECT_EQ(html_escape(""), "");
  EXPECT_EQ(html_escape("&amp;"), "&amp;amp;");  // not idempotent: escape once
}

}  // namespace
}  // namespace wheelpose
