// printable_line: an error message quoting bytes from a damaged file is still one line
// of valid UTF-8.
#include <string>

#include <gtest/gtest.h>

#include "common/base/program.hpp"

namespace slide {
namespace {

TEST(PrintableLine, KeepsValidUtf8AsItIs) {
  const std::string text = "σyy = −66.7 kPa at the base, 𝜀 ≤ 1";
  EXPECT_EQ(printable_line(text), text);
}

TEST(PrintableLine, EscapesLineBreaksAndControlCharacters) {
  EXPECT_EQ(printable_line("a\nb\tc\rd\x7f"), "a\\nb\\tc\\x0dd\\x7f");
}

TEST(PrintableLine, EscapesEachByteOfABrokenSequence) {
  // A lone continuation byte, a lead byte without its continuation, 0xff.
  EXPECT_EQ(printable_line("x\x80y"), "x\\x80y");
  EXPECT_EQ(printable_line("name \xce"), "name \\xce");
  EXPECT_EQ(printable_line("\xff\xfe"), "\\xff\\xfe");
}

TEST(PrintableLine, RefusesOverlongFormsSurrogatesAndCodePointsAboveTheRange) {
  EXPECT_EQ(printable_line("\xc0\xaf"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(printable_line("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // U+D800, a surrogate
  EXPECT_EQ(printable_line("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
  EXPECT_EQ(printable_line("\xf4\x8f\xbf\xbf"), "\xf4\x8f\xbf\xbf");      // U+10FFFF itself
}

}  // namespace
}  // namespace slide
