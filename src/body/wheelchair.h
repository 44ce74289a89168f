#pragma once
// Wheelchairs built from solid primitives (boxes and cylinders), so one description gives both a
// render mesh and an exact inside test for body-vs-chair penetration. Three procedural types:
// everyday manual, sport (cambered wheels, low back, no armrests) and power (base with motor and
// battery, joystick, headrest); dimensions are fitted to the seated body and randomised.

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/random.h"

namespace wheelpose::body {

// kCcBy: the CC-BY "Wheel Chair" model (see load_cc_by_wheelchair), scaled so that its seat
// carries the body; it has no primitives, so no push rims and no exact inside test.
// kNone: no chair at all; the person stands on the floor (people without wheelchairs).
enum class WheelchairType { kManual, kSport, kPower, kCcBy, kNone };
const char* wheelchair_type_name(WheelchairType type);
WheelchairType wheelchair_type_from_name(const std::string& name);  // throws Error

struct Primitive {
  enum Kind { kBox, kCylinder } kind = kBox;
  std::string part;  // "seat", "backrest", "rear_wheel_l", ...
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Matrix3f axes = Eigen::Matrix3f::Identity();  // columns: local x, y, z; cylinder axis = x
  Eigen::Vector3f half =
      Eigen::Vector3f::Zero();  // box: half extents; cylinder: (half length, radius, radius)
  int material = 0;             // index into Wheelchair::colours
};

struct TriMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::array<unsigned, 3>> triangles;
};

struct Wheelchair {
  WheelchairType type = WheelchairType::kManual;
  TriMesh model;  // kCcBy only: the placed model (metres, this chair's frame)
  std::vector<Primitive> parts;
  std::vector<Eigen::Vector3f> colours;  // frame, upholstery, tyre, trim
  float ground_y = 0;                    // floor height under the chair
  nlohmann::ordered_json dimensions;     // what was chosen, for the parameters file
};

// What the chair is fitted to: the seated body's vertices (metres, posed) and joints.
struct SeatFit {
  float hip_width = 0.36f;        // across the hips/thighs
  float thigh_length = 0.42f;     // hip to knee
  float shin_length = 0.42f;      // knee to ankle
  float seat_top = 0;             // lowest body point over the seat footprint
  float seat_front_limit = 0.3f;  // where the calves begin (z): the seat ends before
  float back_z = -0.15f;          // rearmost body point above the seat
  float feet_bottom = -0.5f;      // lowest foot point
  float feet_z = 0.4f;            // mean foot z (footplate centre)
  float armrest_limit = 0.25f;    // height above the seat top the arms leave free beside the hips
  float head_back_z = -0.1f, head_y = 0.7f;  // back of the head and its height
};
SeatFit measure_seat_fit(const std::vector<Eigen::Vector3f>& vertices,
                         const std::vector<int>& body_vertices, const Eigen::Vector3f& left_hip,
                         const Eigen::Vector3f& right_hip, const Eigen::Vector3f& left_knee,
                         const Eigen::Vector3f& left_ankle, const Eigen::Vector3f& head);

// What a type leaves open. A power chair has a tall back and a headrest (a rehab chair) unless
// `headrest` is false: then the lower sling back of a folding power chair, the kind most photos
// of power-chair users show.
struct ChairOptions {
  bool headrest = true;
};

// kNone gives a chair with no parts and no model.
Wheelchair make_wheelchair(WheelchairType type, const SeatFit& fit, RandomStream& stream,
                           const ChairOptions& options = {});
// A chair for nobody (scene object): fitted to an average adult.
Wheelchair make_empty_wheelchair(WheelchairType type, RandomStream& stream);

// Depth of `p` inside the primitive (<= 0 outside).
float inside_depth(const Primitive& prim, const Eigen::Vector3f& p);
// Deepest penetration of any of `points` into any part of the chair.
float max_penetration(const Wheelchair& chair, const std::vector<Eigen::Vector3f>& points,
                      std::string* part = nullptr);

// Sides of a cylinder of `radius` metres in primitive_mesh: 6 to 24, chords of at most 5 mm.
int cylinder_segments(float radius);

// Triangle mesh of all parts of one material (material 0 of a CC-BY chair: its model).
TriMesh primitive_mesh(const Wheelchair& chair, int material);
TriMesh primitive_mesh(const std::vector<Primitive>& parts, int material);

// A cylinder of `radius` from `a` to `b`.
Primitive make_tube(const std::string& part, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                    float radius, int material);

// Vertices ("v") and faces ("f", fans of polygons) of Wavefront OBJ text, as written; `origin`
// names it in errors (origin:line). Written here rather than read with Assimp because Assimp's
// OBJ importer splits vertices per face corner, and .mhclo proxies address the file's vertices
// by their index.
TriMesh parse_obj_mesh(const std::string& text, const std::string& origin);

// The CC-BY "Wheel Chair" by bgamage (sweethome3d-furniture, BlendSwap-CC-BY.sh3f), in metres,
// standing on y = 0, centred in x, its back at z = 0 facing +Z.
TriMesh load_cc_by_wheelchair();
// Height of the model's seat surface: the height bin (1 cm) with the most upward-facing area in
// the middle of the model, between 25 % and 75 % of its height.
float seat_surface_height(const TriMesh& model);
inline constexpr const char* kCcByWheelchairCredit =
    "\"Wheel Chair\" by bgamage (BlendSwap), CC-BY 3.0, via Debian package sweethome3d-furniture";

}  // namespace wheelpose::body
