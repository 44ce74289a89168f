#include "motion/fbx_binary.h"

#include <gtest/gtest.h>

#include <bit>
#include <string>
#include <vector>

#include "core/error.h"
#include "motion/fbx_ascii.h"
#include "motion/fbx_test_reader.h"

namespace wheelpose::motion::fbx {
namespace {

// Every property type, nested children, an empty node and the always-nested AnimationLayer.
std::vector<Node> every_kind_of_node() {
  Node a{"A", {}, {}};
  a.properties = {true,
                  std::int16_t{-12},
                  std::int32_t{-123456},
                  std::int64_t{46186158000},
                  1.5f,
                  -0.1,
                  object_name("pelvis", "Model"),
                  Bytes{std::string("\x00\xff\x01", 3)},
                  std::vector<float>{1.0f, -2.5f},
                  std::vector<double>{0.1, 0.2, 0.3},
                  std::vector<std::int64_t>{0, 1539538600},
                  std::vector<std::int32_t>{24836},
                  std::vector<bool>{true, false, true}};
  Node& child = a.add("Child", {std::string("x")});
  child.add("Grandchild", {std::int32_t{7}});
  a.add("Empty");
  Node layer{"AnimationLayer", {std::int64_t{5}, std::string("layer"), std::string()}, {}};
  return {a, layer, Node{"Last", {std::int32_t{1}}, {}}};
}

TEST(FbxBinary, RoundTripsEveryPropertyType) {
  for (std::uint32_t version : {7400u, 7500u}) {
    const std::vector<Node> nodes = every_kind_of_node();
    const std::string bytes = encode_binary(nodes, version);
    std::uint32_t read_version = 0;
    const std::vector<Node> read = testing::read_binary(bytes, &read_version);
    EXPECT_EQ(read_version, version);
    EXPECT_TRUE(read == nodes) << "version " << version;
    // The footer ends the file on a 16-byte boundary.
    EXPECT_EQ(bytes.size() % 16, 0u);
  }
}

TEST(FbxBinary, GoldenBytesOfOneRecord) {
  const std::string bytes = encode_binary({Node{"Ab", {std::int32_t{1}}, {}}}, 7400);
  // Header: magic (23 bytes) and version 7400 = 0x1CE8.
  EXPECT_EQ(bytes.substr(0, 27), std::string("Kaydara FBX Binary  \0\x1a\0\xe8\x1c\0\0", 27));
  // Record: end offset 27 + 13 + 2 + 5 = 47, one property of 5 bytes, name "Ab", 'I' 1.
  const std::string record(
      "\x2f\0\0\0\x01\0\0\0\x05\0\0\0\x02"
      "AbI\x01\0\0\0",
      20);
  EXPECT_EQ(bytes.substr(27, 20), record);
  // Top-level null record, then the footer id.
  EXPECT_EQ(bytes.substr(47, 13), std::string(13, '\0'));
  EXPECT_EQ(static_cast<unsigned char>(bytes[60]), 0xfa);
  // 60 + 16 = 76, padded to 80; 4 zeros, version, 120 zeros, 16-byte magic.
  EXPECT_EQ(bytes.size(), 80u + 4 + 4 + 120 + 16);
  EXPECT_EQ(bytes.substr(80, 8), std::string("\0\0\0\0\xe8\x1c\0\0", 8));
}

TEST(FbxBinary, NestedNullRecordsWhereTheSdkExpectsThem) {
  const auto first_end_offset = [](const Node& node) {
    const std::string bytes = encode_binary({node}, 7400);
    std::uint32_t end = 0;
    for (int i = 0; i < 4; ++i)
      end |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[27 + i])) << (8 * i);
    return end;
  };
  // Header 27 bytes, then 13 bytes of offsets/counts/name length, the name, the properties, and
  // a 13-byte null record only after children, for nodes without properties, and for
  // AnimationStack/AnimationLayer.
  EXPECT_EQ(first_end_offset(Node{"AnimationLayes", {std::int32_t{1}}, {}}), 27u + 13 + 14 + 5);
  EXPECT_EQ(first_end_offset(Node{"AnimationLayer", {std::int32_t{1}}, {}}),
            27u + 13 + 14 + 5 + 13);
  EXPECT_EQ(first_end_offset(Node{"Empty", {}, {}}), 27u + 13 + 5 + 13);
  Node parent{"P", {std::int32_t{1}}, {}};
  parent.add("C", {std::int32_t{2}});
  EXPECT_EQ(first_end_offset(parent), 27u + 13 + 1 + 5 + (13 + 1 + 5) + 13);
}

TEST(FbxBinary, RejectsNamesTooLongForTheFormat) {
  EXPECT_THROW(encode_binary({Node{std::string(256, 'n'), {}, {}}}, 7400), Error);
}

TEST(FbxAscii, GoldenText) {
  Node model{
      "Model", {std::int64_t{1000}, object_name("pelvis", "Model"), std::string("LimbNode")}, {}};
  model.add("Version", {std::int32_t{232}});
  Node& p = model.add("Properties70");
  add_p(p, "Lcl Translation", "Lcl Translation", "", "A", {0.0, 0.95, -0.1});
  model.add("KeyTime", {std::vector<std::int64_t>{0, 1539538600}});
  model.add("KeyAttrDataFloat", {std::vector<float>{0, std::bit_cast<float>(255790911)}});
  model.add("Flag", {false});
  const std::string text = encode_ascii({model, Node{"References", {}, {}}}, 7400);
  EXPECT_EQ(text,
            "; FBX 7.4.0 project file\n"
            "; ----------------------------------------------------\n\n"
            "Model: 1000, \"Model::pelvis\", \"LimbNode\" {\n"
            "\tVersion: 232\n"
            "\tProperties70:  {\n"
            "\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\", 0, 0.95, -0.1\n"
            "\t}\n"
            "\tKeyTime: *2 {\n"
            "\t\ta: 0,1539538600\n"
            "\t}\n"
            "\tKeyAttrDataFloat: *2 {\n"
            "\t\ta: 0,255790911\n"
            "\t}\n"
            "\tFlag: F\n"
            "}\n"
            "References:  {\n"
            "}\n");
}

TEST(FbxAscii, RefusesWhatTextCannotHold) {
  EXPECT_THROW(encode_ascii({Node{"S", {std::string("a\"b")}, {}}}, 7400), Error);
  EXPECT_THROW(encode_ascii({Node{"S", {std::string("a\nb")}, {}}}, 7400), Error);
  EXPECT_THROW(encode_ascii({Node{"R", {Bytes{"xy"}}, {}}}, 7400), Error);
}

}  // namespace
}  // namespace wheelpose::motion::fbx
