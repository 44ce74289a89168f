#include "body/wheelchair.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "body/assets.h"
#include "core/error.h"

namespace wheelpose::body {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
enum Material { kFrame = 0, kUpholstery = 1, kTyre = 2, kTrim = 3 };

Primitive box(const std::string& part, Eigen::Vector3f lo, Eigen::Vector3f hi, int material) {
  Primitive p;
  p.kind = Primitive::kBox;
  p.part = part;
  p.centre = (lo + hi) / 2;
  p.half = (hi - lo).cwiseAbs() / 2;
  p.material = material;
  return p;
}

// Cylinder along `axis` through `centre`.
Primitive cylinder(const std::string& part, Eigen::Vector3f centre, Eigen::Vector3f axis,
                   float half_length, float radius, int material) {
  Primitive p;
  p.kind = Primitive::kCylinder;
  p.part = part;
  p.centre = centre;
  axis.normalize();
  const Eigen::Vector3f helper =
      std::abs(axis.y()) < 0.9f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitZ();
  const Eigen::Vector3f u = axis.cross(helper).normalized();
  p.axes.col(0) = axis;
  p.axes.col(1) = u;
  p.axes.col(2) = axis.cross(u);
  p.half = {half_length, radius, radius};
  p.material = material;
  return p;
}

// A frame tube between two points.
Primitive tube(const std::string& part, Eigen::Vector3f a, Eigen::Vector3f b, float radius) {
  return make_tube(part, a, b, radius, kFrame);
}

// A ring of tubes (tyre, push rim) around `axis`, so wheels are open like spoked ones.
void add_ring(std::vector<Primitive>& parts, const std::string& part, const Eigen::Vector3f& centre,
              const Eigen::Vector3f& axis, float radius, float tube_radius, int material) {
  constexpr int kSegments = 20;
  const Primitive frame = cylinder(part, centre, axis, 0.01f, radius, material);
  const Eigen::Vector3f u = frame.axes.col(1), w = frame.axes.col(2);
  for (int k = 0; k < kSegments; ++k) {
    const float a0 = 2 * kPi * k / kSegments, a1 = 2 * kPi * (k + 1) / kSegments;
    const Eigen::Vector3f p0 = centre + radius * (std::cos(a0) * u + std::sin(a0) * w);
    const Eigen::Vector3f p1 = centre + radius * (std::cos(a1) * u + std::sin(a1) * w);
    // Slightly longer than the chord so neighbouring segments close the ring.
    Primitive seg = cylinder(part, (p0 + p1) / 2, p1 - p0, (p1 - p0).norm() / 2 + tube_radius / 2,
                             tube_radius, material);
    parts.push_back(seg);
  }
}

// Tyre, spokes, hub and (optionally) push rim of a wheel.
void add_wheel(std::vector<Primitive>& parts, const std::string& suffix, const Eigen::Vector3f& hub,
               const Eigen::Vector3f& axis, float radius, float tyre, bool push_rim, int spokes) {
  add_ring(parts, "wheel" + suffix, hub, axis, radius - tyre, tyre, kTyre);
  parts.push_back(cylinder("hub" + suffix, hub, axis, 0.03f, 0.035f, kTrim));
  const Primitive frame = cylinder("", hub, axis, 0.01f, radius, kTrim);
  for (int k = 0; k < spokes; ++k) {
    const float a = 2 * kPi * k / spokes;
    const Eigen::Vector3f dir = std::cos(a) * frame.axes.col(1) + std::sin(a) * frame.axes.col(2);
    Primitive spoke =
        tube("spoke" + suffix, hub + 0.035f * dir, hub + (radius - 2 * tyre) * dir, 0.004f);
    spoke.material = kTrim;
    parts.push_back(spoke);
  }
  if (push_rim)
    add_ring(parts, "push_rim" + suffix, hub + axis.normalized() * 0.035f, axis, radius - 0.035f,
             0.007f, kTrim);
}

Eigen::Vector3f random_colour(RandomStream& s, float lo, float hi) {
  return {static_cast<float>(s.uniform(lo, hi)), static_cast<float>(s.uniform(lo, hi)),
          static_cast<float>(s.uniform(lo, hi))};
}

}  // namespace

const char* wheelchair_type_name(WheelchairType type) {
  switch (type) {
    case WheelchairType::kManual:
      return "manual";
    case WheelchairType::kSport:
      return "sport";
    case WheelchairType::kPower:
      return "power";
    case WheelchairType::kCcBy:
      return "cc_by";
    case WheelchairType::kNone:
      return "none";
  }
  return "manual";
}

WheelchairType wheelchair_type_from_name(const std::string& name) {
  if (name == "manual") return WheelchairType::kManual;
  if (name == "sport") return WheelchairType::kSport;
  if (name == "power") return WheelchairType::kPower;
  if (name == "cc_by") return WheelchairType::kCcBy;
  if (name == "none") return WheelchairType::kNone;
  throw Error("wheelchair '" + name + "': unknown type (manual, sport, power, cc_by, none)");
}

SeatFit measure_seat_fit(const std::vector<Eigen::Vector3f>& v, const std::vector<int>& body,
                         const Eigen::Vector3f& left_hip, const Eigen::Vector3f& right_hip,
                         const Eigen::Vector3f& left_knee, const Eigen::Vector3f& left_ankle,
                         const Eigen::Vector3f& head) {
  SeatFit f;
  f.thigh_length = (left_knee - left_hip).norm();
  f.shin_length = (left_ankle - left_knee).norm();
  const float hip_y = (left_hip.y() + right_hip.y()) / 2;
  const float hip_z = (left_hip.z() + right_hip.z()) / 2;
  float xmin = 0, xmax = 0;
  f.seat_top = hip_y;
  f.back_z = hip_z;
  f.feet_bottom = left_ankle.y();
  float feet_z_sum = 0;
  int feet_n = 0;
  f.head_back_z = head.z();
  f.head_y = head.y();
  // Hip width: widest points within 12 cm of hip height behind the knees.
  for (int i : body) {
    const Eigen::Vector3f& p = v[i];
    if (std::abs(p.y() - hip_y) < 0.12f && p.z() < hip_z + 0.15f) {
      xmin = std::min(xmin, p.x());
      xmax = std::max(xmax, p.x());
    }
  }
  f.hip_width = xmax - xmin;
  // The seat must end before the calves, which hang below the knees: body points in the front
  // part of the thigh span that lie well below the hip–knee line. (Testing only "below the
  // knee" also caught the buttocks under a raised thigh and left a seat a few cm deep.)
  f.seat_front_limit = left_knee.z();
  const float knee_dz = left_knee.z() - hip_z;
  const float slope = std::abs(knee_dz) > 1e-3f ? (left_knee.y() - hip_y) / knee_dz : 0.0f;
  for (int i : body) {
    const Eigen::Vector3f& p = v[i];
    const float thigh_line_y = hip_y + (p.z() - hip_z) * slope;
    if (p.z() > hip_z + 0.3f * knee_dz && p.y() < thigh_line_y - 0.15f) {
      f.seat_front_limit = std::min(f.seat_front_limit, p.z() - 0.01f);
    }
  }
  const float seat_front = f.seat_front_limit;
  for (int i : body) {
    const Eigen::Vector3f& p = v[i];
    const bool over_seat = p.z() < seat_front && std::abs(p.x()) <= f.hip_width / 2 + 0.05f;
    if (over_seat) f.seat_top = std::min(f.seat_top, p.y());
    if (p.y() < left_ankle.y() + 0.05f && p.z() > seat_front - 0.1f) {
      f.feet_bottom = std::min(f.feet_bottom, p.y());
      feet_z_sum += p.z();
      ++feet_n;
    }
  }
  f.feet_z = feet_n > 0 ? feet_z_sum / feet_n : left_ankle.z() + 0.05f;
  f.armrest_limit = 0.30f;
  for (int i : body) {
    const Eigen::Vector3f& p = v[i];
    if (p.y() >= f.seat_top && p.y() < f.seat_top + 0.7f &&
        std::abs(p.x()) <= f.hip_width / 2 + 0.05f && p.z() < seat_front) {
      f.back_z = std::min(f.back_z, p.z());
    }
    // Arms hanging beside the hips limit the armrest height.
    if (std::abs(p.x()) > f.hip_width / 2 - 0.01f && std::abs(p.x()) < f.hip_width / 2 + 0.12f &&
        p.z() > f.back_z && p.z() < seat_front && p.y() > f.seat_top + 0.08f) {
      f.armrest_limit = std::min(f.armrest_limit, p.y() - f.seat_top);
    }
    if (p.y() > head.y() - 0.12f && p.y() < head.y() + 0.1f && std::abs(p.x()) < 0.1f) {
      f.head_back_z = std::min(f.head_back_z, p.z());
    }
  }
  return f;
}

namespace {

// The CC-BY model under a fitted manual chair's seat: scaled uniformly so that its seat surface
// is at the fitted seat top, its back at the fitted back, centred under the hips.
Wheelchair place_cc_by(Wheelchair manual, const SeatFit& fit) {
  static const TriMesh model = load_cc_by_wheelchair();
  static const float seat = seat_surface_height(model);
  const float ground = manual.ground_y;
  const float scale = (fit.seat_top - 0.003f - ground) / seat;
  Wheelchair c;
  c.type = WheelchairType::kCcBy;
  c.ground_y = ground;
  c.colours = {Eigen::Vector3f(0.4f, 0.4f, 0.42f)};
  c.model = model;
  for (auto& v : c.model.vertices)
    v = Eigen::Vector3f(v.x() * scale, ground + v.y() * scale, fit.back_z - 0.01f + v.z() * scale);
  c.dimensions = {{"type", "cc_by"},
                  {"model", kCcByWheelchairCredit},
                  {"scale", std::round(scale * 1e4) / 1e4},
                  {"seat_height", std::round((fit.seat_top - ground) * 1e4) / 1e4}};
  return c;
}

}  // namespace

float seat_surface_height(const TriMesh& m) {
  Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3f size = hi - lo;
  std::vector<float> area(static_cast<std::size_t>(size.y() * 100) + 2, 0.0f);
  for (const auto& t : m.triangles) {
    const Eigen::Vector3f a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    const Eigen::Vector3f n = (b - a).cross(c - a);
    const Eigen::Vector3f centre = (a + b + c) / 3;
    const Eigen::Vector3f rel = (centre - lo).cwiseQuotient(size);
    if (n.norm() <= 0 || std::abs(n.y()) < 0.9f * n.norm()) continue;  // not horizontal
    if (rel.x() < 0.25f || rel.x() > 0.75f || rel.z() < 0.2f || rel.z() > 0.8f) continue;
    if (rel.y() < 0.25f || rel.y() > 0.75f) continue;
    area[static_cast<std::size_t>((centre.y() - lo.y()) * 100)] += 0.5f * n.norm();
  }
  const auto best = std::max_element(area.begin(), area.end()) - area.begin();
  return lo.y() + (static_cast<float>(best) + 0.5f) / 100.0f;
}

namespace {

// The seat fitted to the body and the frame around it, which every chair type shares.
struct SeatFrame {
  float seat_w, seat_d, hw, top, back, front, cushion, back_h, back_t, plate_top, ground;
};

// Seat, backrest, posts, rails and footplate, fitted to the body: width from the hips, depth
// from the thigh, footplate under the feet. Sets c.ground_y.
SeatFrame add_seat_frame(Wheelchair& c, const SeatFit& fit, RandomStream& s, bool headrest) {
  const bool sport = c.type == WheelchairType::kSport;
  const bool power = c.type == WheelchairType::kPower;
  SeatFrame f;
  f.seat_w = fit.hip_width + static_cast<float>(s.uniform(0.02, 0.06));
  const float gap = 0.003f;
  f.top = fit.seat_top - gap;
  f.back = fit.back_z - gap;
  f.seat_d = std::min(fit.thigh_length * static_cast<float>(s.uniform(0.8, 0.92)),
                      fit.seat_front_limit - f.back);
  f.front = f.back + f.seat_d;
  f.hw = f.seat_w / 2;
  f.cushion = power ? 0.08f : 0.05f;
  // Footplate height from the shin: the feet rest on it.
  f.plate_top = fit.feet_bottom - gap;
  const float plate_clearance = static_cast<float>(s.uniform(0.04, 0.08));
  c.ground_y = f.plate_top - 0.02f - plate_clearance;
  f.ground = c.ground_y;
  const float hw = f.hw, top = f.top, back = f.back, front = f.front, cushion = f.cushion;

  c.parts.push_back(box("seat", {-hw, top - cushion, back}, {hw, top, front}, kUpholstery));
  f.back_h = sport   ? static_cast<float>(s.uniform(0.18, 0.28))
             : power ? static_cast<float>(headrest ? s.uniform(0.50, 0.60) : s.uniform(0.40, 0.50))
                     : static_cast<float>(s.uniform(0.38, 0.48));
  f.back_t = 0.03f;
  c.parts.push_back(
      box("backrest", {-hw, top, back - f.back_t}, {hw, top + f.back_h, back}, kUpholstery));
  // Back posts / canes.
  for (int side : {-1, 1}) {
    const std::string sfx = side < 0 ? "_r" : "_l";
    const float x = side * (hw + 0.012f);
    c.parts.push_back(tube("back_post" + sfx, {x, top - cushion, back - f.back_t},
                           {x, top + f.back_h + (sport ? 0.0f : 0.05f), back - f.back_t}, 0.012f));
    c.parts.push_back(tube("seat_rail" + sfx, {x, top - cushion, back - f.back_t},
                           {x, top - cushion, front}, 0.012f));
    c.parts.push_back(
        tube("front_post" + sfx, {x, top - cushion, front}, {x, f.plate_top, fit.feet_z}, 0.012f));
  }
  // Footplate under the feet.
  const float plate_d = static_cast<float>(s.uniform(0.14, 0.2));
  c.parts.push_back(box("footplate", {-hw, f.plate_top - 0.02f, fit.feet_z - plate_d / 2},
                        {hw, f.plate_top, fit.feet_z + plate_d / 2}, kTrim));
  return f;
}

// Rear wheels with push rims (sport wheels cambered, tops inward) and front casters. Rear
// wheels reach 8-16 cm above the seat (the seated pose puts the seat low).
void add_push_wheels(Wheelchair& c, const SeatFrame& f, RandomStream& s,
                     nlohmann::ordered_json& dims) {
  const bool sport = c.type == WheelchairType::kSport;
  const float r =
      std::clamp((f.top - f.ground + static_cast<float>(s.uniform(0.08, 0.16))) / 2, 0.22f, 0.33f);
  const float camber = sport ? static_cast<float>(s.uniform(12.0, 18.0)) * kPi / 180 : 0.0f;
  const float axle_z = f.back + static_cast<float>(s.uniform(0.0, 0.08));
  for (int side : {-1, 1}) {
    const std::string sfx = side < 0 ? "_r" : "_l";
    // Axis tilted so the wheel's top leans toward the chair (negative camber).
    const Eigen::Vector3f axis(side * std::cos(camber), std::sin(camber), 0);
    const float x = side * (f.hw + 0.05f + r * std::sin(camber));
    const Eigen::Vector3f hub(x, f.ground + r * std::cos(camber), axle_z);
    add_wheel(c.parts, "_rear" + sfx, hub, axis, r, 0.018f, /*push_rim=*/true, sport ? 12 : 8);
    c.parts.push_back(tube("axle" + sfx, hub, {side * (f.hw + 0.012f), hub.y(), axle_z}, 0.01f));
    const float cr = static_cast<float>(sport ? s.uniform(0.03, 0.05) : s.uniform(0.06, 0.1));
    const float cz = f.front - 0.02f;
    const float cx = side * (f.hw + 0.03f);
    c.parts.push_back(
        cylinder("caster" + sfx, {cx, f.ground + cr, cz}, {1, 0, 0}, 0.015f, cr, kTyre));
  }
  dims["rear_wheel_radius"] = r;
  dims["camber_deg"] = camber * 180 / kPi;
}

// Power base: motors, battery box, six small wheels, and (a rehab chair's) a headrest behind
// the head.
void add_power_base(Wheelchair& c, const SeatFrame& f, const SeatFit& fit, RandomStream& s,
                    bool headrest, nlohmann::ordered_json& dims) {
  const float hw = f.hw, back = f.back, front = f.front, ground = f.ground;
  const float base_top =
      std::max(std::min(f.top - f.cushion - 0.05f, ground + 0.35f), ground + 0.14f);
  c.parts.push_back(
      box("base", {-hw + 0.03f, ground + 0.08f, back}, {hw - 0.03f, base_top, front}, kFrame));
  c.parts.push_back(box("battery", {-hw + 0.06f, ground + 0.1f, back - 0.18f},
                        {hw - 0.06f, base_top - 0.04f, back}, kTrim));
  const float r = static_cast<float>(s.uniform(0.14, 0.18));
  for (int side : {-1, 1}) {
    const std::string sfx = side < 0 ? "_r" : "_l";
    const float mid_z = (back + front) / 2;
    c.parts.push_back(cylinder("drive_wheel" + sfx, {side * (hw + 0.03f), ground + r, mid_z},
                               {1, 0, 0}, 0.04f, r, kTyre));
    c.parts.push_back(cylinder("motor" + sfx, {side * (hw - 0.08f), ground + r, mid_z}, {1, 0, 0},
                               0.06f, 0.06f, kTrim));
    for (float z : {back - 0.1f, front + 0.03f}) {
      c.parts.push_back(cylinder(std::string(z < back ? "rear" : "front") + "_caster" + sfx,
                                 {side * (hw - 0.02f), ground + 0.07f, z}, {1, 0, 0}, 0.02f, 0.07f,
                                 kTyre));
    }
  }
  dims["drive_wheel_radius"] = r;
  if (!headrest) {
    dims["headrest"] = false;  // written only when absent, so earlier chairs' records stay
    return;
  }
  const float gap = 0.003f;
  const float hr_z = std::min(fit.head_back_z - gap, back) - 0.04f;
  c.parts.push_back(box("headrest", {-0.12f, fit.head_y - 0.08f, hr_z},
                        {0.12f, fit.head_y + 0.08f, hr_z + 0.04f}, kUpholstery));
  c.parts.push_back(tube("headrest_post", {0, f.top + f.back_h, back - f.back_t / 2},
                         {0, fit.head_y - 0.08f, hr_z + 0.02f}, 0.01f));
}

// Armrests as high as the hanging arms allow; a power chair's joystick on the right one.
void add_armrests(Wheelchair& c, const SeatFrame& f, const SeatFit& fit,
                  nlohmann::ordered_json& dims) {
  const float hw = f.hw, top = f.top, back = f.back, front = f.front;
  const float arm_h = std::clamp(fit.armrest_limit - 0.01f, 0.12f, 0.26f);
  for (int side : {-1, 1}) {
    const std::string sfx = side < 0 ? "_r" : "_l";
    const float x0 = side * (hw + 0.005f), x1 = side * (hw + 0.06f);
    c.parts.push_back(box("armrest" + sfx, {std::min(x0, x1), top + arm_h - 0.04f, back + 0.03f},
                          {std::max(x0, x1), top + arm_h, front - 0.05f}, kUpholstery));
  }
  if (c.type == WheelchairType::kPower) {
    c.parts.push_back(box("joystick_box", {-hw - 0.07f, top + arm_h, front - 0.12f},
                          {-hw - 0.01f, top + arm_h + 0.04f, front - 0.05f}, kTrim));
    c.parts.push_back(cylinder("joystick", {-hw - 0.04f, top + arm_h + 0.07f, front - 0.085f},
                               {0, 1, 0}, 0.03f, 0.008f, kFrame));
  }
  dims["armrest_height"] = arm_h;
}

}  // namespace

Wheelchair make_wheelchair(WheelchairType type, const SeatFit& fit, RandomStream& s,
                           const ChairOptions& options) {
  if (type == WheelchairType::kNone) {
    Wheelchair none;
    none.type = type;
    none.dimensions = {{"type", "none"}};
    return none;
  }
  if (type == WheelchairType::kCcBy)
    return place_cc_by(make_wheelchair(WheelchairType::kManual, fit, s), fit);
  Wheelchair c;
  c.type = type;
  c.colours = {random_colour(s, 0.05f, 0.9f), random_colour(s, 0.02f, 0.25f),
               Eigen::Vector3f(0.05f, 0.05f, 0.05f), random_colour(s, 0.5f, 0.85f)};
  const SeatFrame f = add_seat_frame(c, fit, s, options.headrest);
  nlohmann::ordered_json dims = {{"type", wheelchair_type_name(type)},
                                 {"seat_width", f.seat_w},
                                 {"seat_depth", f.seat_d},
                                 {"seat_height", f.top - f.ground},
                                 {"backrest_height", f.back_h},
                                 {"footplate_height", f.plate_top - f.ground}};
  if (type == WheelchairType::kPower) {
    add_power_base(c, f, fit, s, options.headrest, dims);
  } else {
    add_push_wheels(c, f, s, dims);
  }
  if (type != WheelchairType::kSport) add_armrests(c, f, fit, dims);
  dims["colours"] = nlohmann::ordered_json::array();
  for (const auto& col : c.colours) dims["colours"].push_back({col.x(), col.y(), col.z()});
  c.dimensions = std::move(dims);
  return c;
}

Wheelchair make_empty_wheelchair(WheelchairType type, RandomStream& stream) {
  SeatFit fit;
  fit.seat_top = -0.08f;
  fit.back_z = -0.12f;
  fit.feet_bottom = -0.50f;
  fit.feet_z = 0.36f;
  fit.seat_front_limit = 0.3f;
  fit.head_y = 0.62f;
  fit.head_back_z = -0.08f;
  return make_wheelchair(type, fit, stream);
}

float inside_depth(const Primitive& prim, const Eigen::Vector3f& p) {
  const Eigen::Vector3f local = prim.axes.transpose() * (p - prim.centre);
  if (prim.kind == Primitive::kBox) {
    return (prim.half - local.cwiseAbs()).minCoeff();
  }
  const float radial = std::hypot(local.y(), local.z());
  return std::min(prim.half.x() - std::abs(local.x()), prim.half.y() - radial);
}

float max_penetration(const Wheelchair& chair, const std::vector<Eigen::Vector3f>& points,
                      std::string* part) {
  float worst = 0;
  for (const Primitive& prim : chair.parts) {
    const float reach = prim.half.norm();
    for (const Eigen::Vector3f& p : points) {
      if ((p - prim.centre).squaredNorm() > reach * reach) continue;
      const float d = inside_depth(prim, p);
      if (d > worst) {
        worst = d;
        if (part != nullptr) *part = prim.part;
      }
    }
  }
  return worst;
}

Primitive make_tube(const std::string& part, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                    float radius, int material) {
  return cylinder(part, (a + b) / 2, b - a, (b - a).norm() / 2, radius, material);
}

TriMesh primitive_mesh(const Wheelchair& chair, int material) {
  if (!chair.model.vertices.empty()) return material == 0 ? chair.model : TriMesh{};
  return primitive_mesh(chair.parts, material);
}

int cylinder_segments(float radius) {
  // Chords of at most 5 mm (about a pixel at 3 m in a 1280×720, 50° frame): a 4 mm spoke gets
  // 6 sides instead of 24, which cuts a manual chair's triangles by more than half.
  constexpr float kMaxChord = 0.005f;
  const float n = std::ceil(2 * kPi * radius / kMaxChord);
  return static_cast<int>(std::clamp(n, 6.0f, 24.0f));
}

TriMesh primitive_mesh(const std::vector<Primitive>& parts, int material) {
  TriMesh m;
  auto add_quad = [&](const std::array<Eigen::Vector3f, 4>& q, const Eigen::Vector3f& n) {
    const unsigned base = static_cast<unsigned>(m.vertices.size());
    for (const auto& p : q) {
      m.vertices.push_back(p);
      m.normals.push_back(n);
    }
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  };
  for (const Primitive& prim : parts) {
    if (prim.material != material) continue;
    auto world = [&](const Eigen::Vector3f& l) -> Eigen::Vector3f {
      return prim.centre + prim.axes * l;
    };
    if (prim.kind == Primitive::kBox) {
      const Eigen::Vector3f h = prim.half;
      for (int axis = 0; axis < 3; ++axis) {
        for (int sign : {-1, 1}) {
          const int a = (axis + 1) % 3, b = (axis + 2) % 3;
          std::array<Eigen::Vector3f, 4> q;
          const float sa[4] = {-1, 1, 1, -1}, sb[4] = {-1, -1, 1, 1};
          for (int k = 0; k < 4; ++k) {
            Eigen::Vector3f l;
            l[axis] = sign * h[axis];
            l[a] = sa[k] * h[a];
            l[b] = sign * sb[k] * h[b];
            q[k] = world(l);
          }
          Eigen::Vector3f n = Eigen::Vector3f::Zero();
          n[axis] = static_cast<float>(sign);
          add_quad(q, prim.axes * n);
        }
      }
    } else {
      const float hl = prim.half.x(), r = prim.half.y();
      const int kSegments = cylinder_segments(r);
      for (int k = 0; k < kSegments; ++k) {
        const float a0 = 2 * kPi * k / kSegments, a1 = 2 * kPi * (k + 1) / kSegments;
        const Eigen::Vector3f d0(0, std::cos(a0), std::sin(a0)), d1(0, std::cos(a1), std::sin(a1));
        const Eigen::Vector3f ax(hl, 0, 0);
        add_quad({world(-ax + r * d0), world(-ax + r * d1), world(ax + r * d1), world(ax + r * d0)},
                 prim.axes * ((d0 + d1) / 2).normalized());
        // End caps as triangles fanning from the axis.
        for (int sign : {-1, 1}) {
          const unsigned base = static_cast<unsigned>(m.vertices.size());
          const Eigen::Vector3f n = prim.axes * Eigen::Vector3f(static_cast<float>(sign), 0, 0);
          m.vertices.push_back(world(sign * ax));
          m.vertices.push_back(world(sign * ax + r * (sign > 0 ? d0 : d1)));
          m.vertices.push_back(world(sign * ax + r * (sign > 0 ? d1 : d0)));
          for (int i = 0; i < 3; ++i) m.normals.push_back(n);
          m.triangles.push_back({base, base + 1, base + 2});
        }
      }
    }
  }
  return m;
}

TriMesh parse_obj_mesh(const std::string& text, const std::string& origin) {
  TriMesh m;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.rfind("v ", 0) == 0) {
      std::istringstream ls(line.substr(2));
      Eigen::Vector3f v;
      if (!(ls >> v.x() >> v.y() >> v.z())) {
        throw Error(origin + ":" + std::to_string(line_no) + ": bad vertex");
      }
      m.vertices.push_back(v);
    } else if (line.rfind("f ", 0) == 0) {
      std::istringstream ls(line.substr(2));
      std::vector<unsigned> idx;
      std::string token;
      while (ls >> token) {
        const long i = std::strtol(token.c_str(), nullptr, 10);
        const long n = static_cast<long>(m.vertices.size());
        const long resolved = i < 0 ? n + i : i - 1;
        if (resolved < 0 || resolved >= n) {
          throw Error(origin + ":" + std::to_string(line_no) + ": bad face");
        }
        idx.push_back(static_cast<unsigned>(resolved));
      }
      for (std::size_t k = 2; k < idx.size(); ++k)
        m.triangles.push_back({idx[0], idx[k - 1], idx[k]});
    }
  }
  if (m.vertices.empty() || m.triangles.empty()) throw Error(origin + ": no geometry");
  return m;
}

TriMesh load_cc_by_wheelchair() {
  const std::string entry = "blendswap-cc-by/wheelchair/wheelchair.obj";
  const auto archive = sweethome3d_archive();
  TriMesh m = parse_obj_mesh(read_zip_entry(archive, entry), archive.string() + ": " + entry);
  for (auto& v : m.vertices) v *= 0.01f;  // centimetres -> metres
  Eigen::Vector3f lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3f shift(-(lo.x() + hi.x()) / 2, -lo.y(), -lo.z());
  for (auto& v : m.vertices) v += shift;
  return m;
}

}  // namespace wheelpose::body
