#include "core/config.h"

#include <gtest/gtest.h>

#include <functional>

#include "core/error.h"

namespace wheelpose {
namespace {

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(ConfigNode, ReadsTypedValuesWithDefaults) {
  auto root = ConfigNode::load_string("filter:\n  cutoff_hz: 5\n  order: 3\nname: x\n", "c.yaml");
  auto filter = root.child("filter");
  EXPECT_EQ(filter.get_double("cutoff_hz", 1, 0, 100), 5.0);
  EXPECT_EQ(filter.get_int("order", 1, 1, 8), 3);
  EXPECT_EQ(filter.get_bool("enabled", true), true);
  filter.finish();
  EXPECT_EQ(root.get_string("name", ""), "x");
  root.finish();
}

TEST(ConfigNode, RejectsUnknownKeyWithLine) {
  auto root = ConfigNode::load_string("a: 1\nfilter:\n  cutoff_hz: 5\n  cutof: 3\n", "c.yaml");
  auto filter = root.child("filter");
  filter.get_double("cutoff_hz", 1, 0, 100);
  EXPECT_EQ(error_of([&] { filter.finish(); }), "c.yaml:4: key 'filter.cutof': unknown key");
}

TEST(ConfigNode, RejectsWrongTypeAndRange) {
  auto root = ConfigNode::load_string("fps: fast\norder: 12\nmode: z\n", "c.yaml");
  EXPECT_EQ(error_of([&] { root.get_double("fps", 20, 1, 1000); }),
            "c.yaml:1: key 'fps': expected a number, got 'fast'");
  EXPECT_EQ(error_of([&] { root.get_int("order", 3, 1, 8); }),
            "c.yaml:2: key 'order': value 12 is outside [1, 8]");
  EXPECT_EQ(error_of([&] {
              root.get_choice("mode", "a", {"a", "b"});
            }),
            "c.yaml:3: key 'mode': 'z' is not one of: a, b");
}

TEST(ConfigNode, ReportsSyntaxErrorsAndMissingFiles) {
  EXPECT_EQ(
      error_of([] { ConfigNode::load_string("a: [1, 2\n", "bad.yaml"); }).rfind("bad.yaml:", 0),
      0u);
  EXPECT_EQ(error_of([] { ConfigNode::load_file("/nonexistent/x.yaml"); }),
            "/nonexistent/x.yaml: cannot open config file");
}

TEST(SetDottedKey, WritesOneKeyAndMakesTheMapsOnTheWay) {
  YAML::Node root = YAML::Load("labels:\n  keypoint_template: coco17\nimage: {width: 64}\n");
  set_dotted_key(root, "labels.box", YAML::Load("person_and_wheelchair"));
  set_dotted_key(root, "randomizers.Camera.fov", YAML::Load("[40, 60]"));
  set_dotted_key(root, "image.width", YAML::Load("128"));
  EXPECT_EQ(root["labels"]["keypoint_template"].as<std::string>(), "coco17");  // kept
  EXPECT_EQ(root["labels"]["box"].as<std::string>(), "person_and_wheelchair");
  EXPECT_EQ(root["randomizers"]["Camera"]["fov"][1].as<int>(), 60);
  EXPECT_EQ(root["image"]["width"].as<int>(), 128);
  EXPECT_EQ(error_of([&] { set_dotted_key(root, "image.width.x", YAML::Load("1")); }),
            "key 'image.width.x': 'image.width' is not a map of keys");
  EXPECT_EQ(error_of([&] { set_dotted_key(root, "labels..box", YAML::Load("1")); }),
            "key 'labels..box': an empty name between dots");
}

}  // namespace
}  // namespace wheelpose
