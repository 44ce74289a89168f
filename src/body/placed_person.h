#pragma once
// A built person (body/person.h) made ready for a scene: the body split into the regions an
// outfit covers (skin, top, bottom, shoes), the MakeHuman garments worn, the wheelchair's parts
// and the mobility aid's parts, each a mesh placed in the world with normals, UVs and the paint
// it wears. The scene side (generate's frame builder) only turns parts into instances and
// materials; what covers what is decided here.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "body/person.h"
#include "body/rig.h"
#include "body/wheelchair.h"

namespace wheelpose::body {

// Which regions of the body an outfit's top and bottom reach; the rest shows skin. (A worn
// MakeHuman suit covers the body whatever this says.)
struct DressCode {
  bool long_sleeves = true;
  bool long_trousers = true;
};

// What colours a part: the person's skin, one of the outfit's colours, or the part's own
// (a wheelchair's or mobility aid's colour).
enum class Paint { kSkin, kLips, kTop, kBottom, kShoes, kHair, kEyes, kOwnColour };
enum class PartOwner { kBody, kWheelchair, kMobilityAid };

struct PlacedPart {
  std::string name;  // "skin", "top", a garment's name ("casualsuit01"), "wheelchair_frame", …
  PartOwner owner = PartOwner::kBody;
  Paint paint = Paint::kSkin;
  int material = 0;  // of a wheelchair (0 frame, 1 upholstery, 2 tyre, 3 trim) or aid (0, 1)
  Eigen::Vector3f colour = Eigen::Vector3f::Ones();  // for kSkin and kOwnColour
  std::vector<Eigen::Vector3f> positions;            // world
  std::vector<Eigen::Vector3f> normals;              // world, unit
  std::vector<Eigen::Vector2f> uvs;                  // body and garments only
  std::vector<Eigen::Vector3i> triangles;
};

// The person's parts in scene order (body regions, garments, wheelchair, mobility aid), each
// placed by `to_world` (a similarity); parts without triangles are left out.
std::vector<PlacedPart> place_person(const Person& person, const Rig& rig, const DressCode& dress,
                                     const Eigen::Affine3f& to_world);

// A body-stage mesh (chair part, aid part, furniture model) placed by `to_world`: positions,
// normals turned and renormalized, triangles; name, owner and paint left at their defaults.
PlacedPart placed_mesh(const TriMesh& mesh, const Eigen::Affine3f& to_world);

// An unoccupied wheelchair's parts ("frame", "upholstery", "tyre", "trim"), placed.
std::vector<PlacedPart> place_wheelchair(const Wheelchair& chair, const Eigen::Affine3f& to_world);

}  // namespace wheelpose::body
