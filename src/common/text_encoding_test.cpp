#include "common/text_encoding.h"

#include <string>

#include <gtest/gtest.h>

namespace cmcsurf {
namespace {

// The test vectors of RFC 4648, section 10, and bytes with the high bit set (a signed char
// must not sign-extend into the alphabet index).
TEST(TextEncoding, Base64OfRfc4648Vectors) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\x00\x80", 3)), "/wCA");
  EXPECT_EQ(base64(std::string("\xfb\xff", 2)), "+/8=");  // the last two letters
}

TEST(TextEncoding, HtmlEscapeLeavesTheApostrophe) {
  EXPECT_EQ(html_escape("a<b>&\"c\"'d'"), "a&lt;b&gt;&amp;&quot;c&quot;'d'");
  EXPECT_EQ(html_escape("plain ü"), "plain ü");  // UTF-8 passes through
}

TEST(TextEncoding, XmlEscapeAlsoEscapesTheApostrophe) {
  EXPECT_EQ(xml_escape("a<b>&\"c\"'d'"), "a&lt;b&gt;&amp;&quot;c&quot;&apos;d&apos;");
  EXPECT_EQ(xml_escape(""), "");
}

}  // namespace
}  // namespace cmcsurf
