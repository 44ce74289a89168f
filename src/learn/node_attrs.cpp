#include "learn/node_attrs.h"

#include "core/error.h"

namespace wheelpose::learn {

void NodeAttrs::fail(const std::string& message) const {
  throw Error(model_.where(node_) + ": " + message);
}

const AttrValue* NodeAttrs::find(const std::string& key, AttrValue::Kind kind) const {
  const AttrValue* a = node().attr(key);
  if (a != nullptr && a->kind != kind) fail("attr '" + key + "' has the wrong type");
  return a;
}

std::int64_t NodeAttrs::i(const std::string& key, std::optional<std::int64_t> fallback) const {
  if (const AttrValue* a = find(key, AttrValue::Kind::kInt)) return a->i;
  if (!fallback) fail("attr '" + key + "' is missing");
  return *fallback;
}

bool NodeAttrs::b(const std::string& key, bool fallback) const {
  const AttrValue* a = find(key, AttrValue::Kind::kBool);
  return a ? a->b : fallback;
}

double NodeAttrs::f(const std::string& key, double fallback) const {
  const AttrValue* a = find(key, AttrValue::Kind::kFloat);
  return a ? a->f : fallback;
}

std::string NodeAttrs::s(const std::string& key, std::optional<std::string> fallback) const {
  if (const AttrValue* a = find(key, AttrValue::Kind::kString)) return a->s;
  if (!fallback) fail("attr '" + key + "' is missing");
  return *fallback;
}

std::vector<std::int64_t> NodeAttrs::ints(const std::string& key,
                                          std::optional<std::vector<std::int64_t>> fallback) const {
  if (const AttrValue* a = find(key, AttrValue::Kind::kList)) return a->ints;
  if (!fallback) fail("attr '" + key + "' is missing");
  return *fallback;
}

std::vector<std::string> NodeAttrs::strings(const std::string& key) const {
  const AttrValue* a = find(key, AttrValue::Kind::kList);
  return a ? a->strings : std::vector<std::string>{};
}

std::optional<DType> NodeAttrs::type(const std::string& key) const {
  const AttrValue* a = find(key, AttrValue::Kind::kType);
  return a ? std::optional<DType>(a->type) : std::nullopt;
}

void NodeAttrs::inputs(std::size_t min, std::size_t max) const {
  const std::size_t k = node().inputs.size();
  if (k < min || k > max) {
    fail("has " + std::to_string(k) + " inputs, expected " +
         (min == max ? std::to_string(min) : std::to_string(min) + ".." + std::to_string(max)));
  }
}

void NodeAttrs::nhwc() const {
  const std::string format = s("data_format", std::string("NHWC"));
  if (format != "NHWC") fail("data_format '" + format + "' is not supported (only NHWC)");
}

std::array<std::int64_t, 2> NodeAttrs::hw(const std::string& key, std::int64_t fallback) const {
  const std::vector<std::int64_t> v =
      ints(key, std::vector<std::int64_t>{1, fallback, fallback, 1});
  if (v.size() != 4 || v[0] != 1 || v[3] != 1 || v[1] < 1 || v[2] < 1) {
    fail("attr '" + key + "' must be [1, h, w, 1] with h, w >= 1");
  }
  return {v[1], v[2]};
}

ops::Padding NodeAttrs::padding() const {
  ops::Padding p;
  const std::string kind = s("padding");
  if (kind == "SAME") {
    p.kind = ops::Padding::Kind::kSame;
  } else if (kind == "VALID") {
    p.kind = ops::Padding::Kind::kValid;
  } else if (kind == "EXPLICIT") {
    p.kind = ops::Padding::Kind::kExplicit;
    const std::vector<std::int64_t> e = ints("explicit_paddings");
    if (e.size() != 8 || e[0] != 0 || e[1] != 0 || e[6] != 0 || e[7] != 0) {
      fail("explicit_paddings must be 8 values padding only H and W");
    }
    p.top = e[2];
    p.bottom = e[3];
    p.left = e[4];
    p.right = e[5];
  } else {
    fail("padding '" + kind + "' is not SAME, VALID or EXPLICIT");
  }
  return p;
}

}  // namespace wheelpose::learn
