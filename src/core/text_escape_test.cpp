#include "core/text_escape.h"

#include <gtest/gtest.h>

namespace wheelpose {
namespace {

using namespace std::string_literals;

TEST(TextEscape, ValidUtf8IsRecognised) {
  EXPECT_TRUE(is_valid_utf8("plain"));
  EXPECT_TRUE(is_valid_utf8("Zürich, 東京, 🦽"));
  EXPECT_FALSE(is_valid_utf8("\xFF"));
  EXPECT_FALSE(is_valid_utf8("caf\xE9"));           // Latin-1 é
  EXPECT_FALSE(is_valid_utf8("\xC0\xAF"));          // overlong '/'
  EXPECT_FALSE(is_valid_utf8("\xED\xA0\x80"));      // a UTF-16 surrogate
  EXPECT_FALSE(is_valid_utf8("\xF4\x90\x80\x80"));  // above U+10FFFF
  EXPECT_FALSE(is_valid_utf8("\xE2\x82"));          // cut short
}

TEST(TextEscape, InvisibleBytesBecomeVisible) {
  EXPECT_EQ(escape_bytes("Zürich 🦽"), "Zürich 🦽");
  EXPECT_EQ(escape_bytes("a\0b"s), "a\\x00b");
  EXPECT_EQ(escape_bytes("\xEF\xBB\xBF"
                         "0"),
            "\\xEF\\xBB\\xBF0");
  EXPECT_EQ(escape_bytes("caf\xE9.jpg"), "caf\\xE9.jpg");
  EXPECT_EQ(escape_bytes("tab\there\r\n\x7F"), "tab\\x09here\\x0D\\x0A\\x7F");
  // Escaping twice is escaping once: main escapes messages that already quote escaped text.
  EXPECT_EQ(escape_bytes(escape_bytes("a\0b"s)), "a\\x00b");
}

}  // namespace
}  // namespace wheelpose
