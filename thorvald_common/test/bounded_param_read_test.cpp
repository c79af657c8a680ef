// The bounds a parameter-server reply is checked against before it is parsed (bounded_param_read.h), without a master.
#include <gtest/gtest.h>

#include <string>

#include "thorvald_common/ros/bounded_param_read.h"

namespace thorvald_common {
namespace {

/// `n` scalars in an XML-RPC list, as the master encodes one.
std::string list(int n) {
  std::string xml = "<value><array><data>\n";
  for (int i = 0; i < n; ++i) xml += "<value><double>1.0</double></value>\n";
  return xml + "</data></array></value>";
}

/// A list nested `depth` levels deep around one scalar.
std::string nested(int depth) {
  std::string xml = "<value><int>1</int></value>";
  for (int i = 0; i < depth; ++i) xml = "<value><array><data>" + xml + "</data></array></value>";
  return xml;
}

TEST(BoundedParamRead, ValuesAreCountedBeforeParsing) {
  EXPECT_EQ(exceededBound(list(10), 11, 8), XmlRpcBound::kNone);  // ten scalars and the list itself
  EXPECT_EQ(exceededBound(list(10), 10, 8), XmlRpcBound::kValues);
  EXPECT_EQ(exceededBound(list(20001), 20000, 8), XmlRpcBound::kValues);
}

TEST(BoundedParamRead, NestingIsBounded) {
  EXPECT_EQ(exceededBound(nested(8), 100, 8), XmlRpcBound::kNone);
  EXPECT_EQ(exceededBound(nested(9), 100, 8), XmlRpcBound::kDepth);
  // Siblings do not add up: depth is nesting, not the number of lists.
  std::string wide = "<value><array><data>";
  for (int i = 0; i < 20; ++i) wide += nested(3);
  wide += "</data></array></value>";
  EXPECT_EQ(exceededBound(wide, 1000, 4), XmlRpcBound::kNone);
}

TEST(BoundedParamRead, MapsCountLikeLists) {
  const std::string map =
      "<value><struct><member><name>drive0</name><value><struct><member><name>x</name><value><double>0.5</double>"
      "</value></member></struct></value></member></struct></value>";
  EXPECT_EQ(exceededBound(map, 3, 2), XmlRpcBound::kNone);
  EXPECT_EQ(exceededBound(map, 3, 1), XmlRpcBound::kDepth);
  EXPECT_EQ(exceededBound(map, 2, 2), XmlRpcBound::kValues);
}

TEST(BoundedParamRead, EscapedTextIsNoTag) {
  // Strings reach the reply escaped: "&lt;value&gt;" inside a string is text, not a value.
  const std::string text = "<value><string>&lt;value&gt;&lt;array&gt;</string></value>";
  EXPECT_EQ(exceededBound(text, 1, 0), XmlRpcBound::kNone);
}

}  // namespace
}  // namespace thorvald_common
