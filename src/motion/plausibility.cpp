#include "motion/plausibility.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>

namespace wheelpose::motion {

namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// Normal adult active ranges of motion from the American Academy of Orthopaedic Surgeons
// ("Joint Motion: Method of Measuring and Recording", AAOS 1965; Greene & Heckman, "The Clinical
// Measurement of Joint Motion", AAOS 1994): elbow flexion 150 (the rule uses 155), shoulder
// extension 60, horizontal adduction 135 from 90 degrees of abduction (45 across the frontal
// plane), shoulder internal rotation 70 / external rotation 90, cervical flexion 45 / extension
// 45 / lateral bending 45 / rotation 60, thoracolumbar flexion 80 / extension 25 / lateral
// bending 35 / rotation 45. Clavicle elevation about 45 and depression about 10 (Kapandji, "The
// Physiology of the Joints", vol. 1). Angles measured from joint positions carry some error, so
// most rules allow a 5-10 degree tolerance beyond the published value.
constexpr double kElbowFlexionMax = 155.0;
constexpr double kArmExtensionMax = 60.0;
constexpr double kArmAdductionMax = 55.0;      // 45 + 10 tolerance
constexpr double kHumeralRotationMax = 100.0;  // internal 70 / external 90 + tolerance
constexpr double kClavicleElevationMax = 45.0;
constexpr double kClavicleDepressionMax = 15.0;
constexpr double kNeckFlexionMax = 50.0;
constexpr double kNeckExtensionMax = 50.0;
constexpr double kNeckLateralMax = 50.0;
constexpr double kTrunkFlexionMax = 85.0;
constexpr double kTrunkExtensionMax = 30.0;
constexpr double kTrunkLateralMax = 40.0;
constexpr double kTrunkTwistMax = 50.0;
// Bones may change by 2% or 5 mm (whichever is larger) from the first frame.
constexpr double kBoneChangeFraction = 0.02;
constexpr double kBoneChangeMin = 0.005;
// Cores of the trunk, neck and head (metres) that an arm may not enter: smaller than the real
// body (trunk about 0.15 x 0.10 m half-size) so that hands and forearms may rest on its surface.
constexpr double kTrunkCoreRadius = 0.085;
constexpr double kNeckCoreRadius = 0.045;
constexpr double kHeadCoreRadius = 0.07;

// Orthonormal frame (columns left, up, forward) from an up vector and a left-right vector.
Matrix3d body_frame(const Vector3d& up_vector, const Vector3d& left_vector) {
  const Vector3d up = up_vector.normalized();
  const Vector3d left = (left_vector - left_vector.dot(up) * up).normalized();
  Matrix3d frame;
  frame.col(0) = left;
  frame.col(1) = up;
  frame.col(2) = left.cross(up);
  return frame;
}

double point_segment_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

// Smallest distance between segment pq (sampled finely) and segment ab.
double segment_distance(const Vector3d& p, const Vector3d& q, const Vector3d& a,
                        const Vector3d& b) {
  constexpr int kSamples = 24;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSamples; ++i) {
    const Vector3d point = p + (q - p) * (static_cast<double>(i) / kSamples);
    best = std::min(best, point_segment_distance(point, a, b));
  }
  return best;
}

std::string format(const char* pattern, double a, double b = 0.0) {
  char buffer[200];
  std::snprintf(buffer, sizeof(buffer), pattern, a, b);
  return buffer;
}

// Collects one entry per rule: the first offending frame's message and how many frames broke it.
class ProblemLog {
 public:
  void add(const std::string& rule, std::size_t frame, const std::string& message) {
    auto [it, inserted] = entries_.try_emplace(rule);
    if (inserted) {
      order_.push_back(rule);
      it->second.first_frame = frame;
      it->second.message = message;
    }
    ++it->second.count;
  }
  std::vector<std::string> result(std::size_t frame_count) const {
    std::vector<std::string> out;
    for (const std::string& rule : order_) {
      const Entry& e = entries_.at(rule);
      out.push_back(e.message + " at frame " + std::to_string(e.first_frame) + " (" +
                    std::to_string(e.count) + " of " + std::to_string(frame_count) + " frames)");
    }
    return out;
  }

 private:
  struct Entry {
    std::size_t first_frame = 0;
    std::size_t count = 0;
    std::string message;
  };
  std::map<std::string, Entry> entries_;
  std::vector<std::string> order_;
};

}  // namespace

PoseAngles measure_pose_angles(const Pose& p) {
  PoseAngles a{};
  const Matrix3d thorax =
      body_frame(p[kNeckBase] - p[kUpperChest], p[kLeftClavicle] - p[kRightClavicle]);
  const Matrix3d pelvis = body_frame(p[kSpine] - p[kPelvis], p[kLeftHip] - p[kRightHip]);
  for (int side = 0; side < 2; ++side) {
    const bool left = side == 0;
    const double sign = left ? 1.0 : -1.0;
    const int clavicle = left ? kLeftClavicle : kRightClavicle;
    const int shoulder = left ? kLeftShoulder : kRightShoulder;
    const int elbow = left ? kLeftElbow : kRightElbow;
    const int wrist = left ? kLeftWrist : kRightWrist;
    const Vector3d upper = p[elbow] - p[shoulder];
    const Vector3d fore = p[wrist] - p[elbow];
    a.elbow_flexion[side] =
        std::acos(std::clamp(upper.normalized().dot(fore.normalized()), -1.0, 1.0)) * kRadToDeg;
    const Vector3d d = (thorax.transpose() * upper).normalized();
    a.arm_extension[side] = std::asin(std::clamp(-d.z(), -1.0, 1.0)) * kRadToDeg;
    a.arm_adduction[side] = std::asin(std::clamp(-sign * d.x(), -1.0, 1.0)) * kRadToDeg;
    // Undo the swing of the hanging arm to its direction; the forearm's bearing about the arm
    // axis is then the axial rotation (0 = forearm forward when the arm hangs).
    const double elevation = std::acos(std::clamp(-d.y(), -1.0, 1.0)) * kRadToDeg;
    a.humeral_rotation[side] = std::numeric_limits<double>::quiet_NaN();
    if (a.elbow_flexion[side] > 15.0 && elevation < 150.0) {
      const Quaterniond swing = Quaterniond::FromTwoVectors(Vector3d(0, -1, 0), d);
      const Vector3d u = swing.conjugate() * (thorax.transpose() * fore);
      a.humeral_rotation[side] = std::atan2(-sign * u.x(), u.z()) * kRadToDeg;
    }
    const Vector3d c = thorax.transpose() * (p[shoulder] - p[clavicle]);
    a.clavicle_elevation[side] = std::asin(std::clamp(c.normalized().y(), -1.0, 1.0)) * kRadToDeg;
  }
  const Vector3d head = thorax.transpose() * (p[kHeadTop] - p[kHeadBase]);
  a.neck_flexion = std::atan2(head.z(), head.y()) * kRadToDeg;
  a.neck_lateral = std::atan2(head.x(), head.y()) * kRadToDeg;
  const Vector3d trunk = pelvis.transpose() * (p[kNeckBase] - p[kSpine]);
  a.trunk_flexion = std::atan2(trunk.z(), trunk.y()) * kRadToDeg;
  a.trunk_lateral = std::atan2(trunk.x(), trunk.y()) * kRadToDeg;
  const Vector3d shoulder_line = pelvis.transpose() * thorax.col(0);
  a.trunk_twist = std::atan2(-shoulder_line.z(), shoulder_line.x()) * kRadToDeg;
  return a;
}

std::vector<std::string> plausibility_problems(const std::vector<Pose>& frames) {
  ProblemLog log;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Pose& p = frames[f];
    bool finite = true;
    for (const Vector3d& joint : p) finite = finite && joint.allFinite();
    if (!finite) {
      log.add("finite", f, "non-finite joint position");
      continue;
    }
    const PoseAngles a = measure_pose_angles(p);
    for (int side = 0; side < 2; ++side) {
      const std::string s = side == 0 ? "left" : "right";
      if (a.elbow_flexion[side] > kElbowFlexionMax) {
        log.add(s + "elbow", f,
                s + format(" elbow flexion %.1f deg beyond %.0f", a.elbow_flexion[side],
                           kElbowFlexionMax));
      }
      const double rotation = a.humeral_rotation[side];
      if (!std::isnan(rotation) && std::abs(rotation) > kHumeralRotationMax) {
        log.add(s + "rotation", f,
                s + format(" elbow bends the wrong way (hyperextension): upper-arm rotation %.1f "
                           "deg beyond +-%.0f",
                           rotation, kHumeralRotationMax));
      }
      if (a.arm_extension[side] > kArmExtensionMax) {
        log.add(s + "extension", f,
                s + format(" shoulder extension %.1f deg beyond %.0f", a.arm_extension[side],
                           kArmExtensionMax));
      }
      if (a.arm_adduction[side] > kArmAdductionMax) {
        log.add(s + "adduction", f,
                s + format(" shoulder horizontal adduction %.1f deg beyond %.0f",
                           a.arm_adduction[side], kArmAdductionMax));
      }
      if (a.clavicle_elevation[side] > kClavicleElevationMax ||
          a.clavicle_elevation[side] < -kClavicleDepressionMax) {
        log.add(s + "clavicle", f,
                s + format(" clavicle elevation %.1f deg outside [-%.0f, 45]",
                           a.clavicle_elevation[side], kClavicleDepressionMax));
      }
    }
    if (a.neck_flexion > kNeckFlexionMax || a.neck_flexion < -kNeckExtensionMax) {
      log.add(
          "neckflexion", f,
          format("neck flexion %.1f deg outside [-%.0f, 50]", a.neck_flexion, kNeckExtensionMax));
    }
    if (std::abs(a.neck_lateral) > kNeckLateralMax) {
      log.add("necklateral", f,
              format("neck lateral bend %.1f deg beyond +-%.0f", a.neck_lateral, kNeckLateralMax));
    }
    if (a.trunk_flexion > kTrunkFlexionMax || a.trunk_flexion < -kTrunkExtensionMax) {
      log.add("trunkflexion", f,
              format("trunk flexion %.1f deg outside [-%.0f, 85]", a.trunk_flexion,
                     kTrunkExtensionMax));
    }
    if (std::abs(a.trunk_lateral) > kTrunkLateralMax) {
      log.add(
          "trunklateral", f,
          format("trunk lateral bend %.1f deg beyond +-%.0f", a.trunk_lateral, kTrunkLateralMax));
    }
    if (std::abs(a.trunk_twist) > kTrunkTwistMax) {
      log.add("trunktwist", f,
              format("trunk twist %.1f deg beyond +-%.0f", a.trunk_twist, kTrunkTwistMax));
    }
    // Bone lengths against the first frame.
    for (int j = 0; j < kJointCount; ++j) {
      const int parent = joint_parent(j);
      if (parent < 0) continue;
      const double length0 = (frames[0][j] - frames[0][parent]).norm();
      const double length = (p[j] - p[parent]).norm();
      if (std::abs(length - length0) > std::max(kBoneChangeMin, kBoneChangeFraction * length0)) {
        log.add("bone" + std::to_string(j), f,
                "bone " + std::string(joint_name(parent)) + "-" + std::string(joint_name(j)) +
                    format(" changes length from %.3f m to %.3f m", length0, length));
      }
    }
    // Arms through the trunk, neck or head.
    struct Core {
      int from, to;
      double radius;
      const char* name;
    };
    const Core cores[] = {{kPelvis, kSpine, kTrunkCoreRadius, "trunk"},
                          {kSpine, kChest, kTrunkCoreRadius, "trunk"},
                          {kChest, kUpperChest, kTrunkCoreRadius, "trunk"},
                          {kUpperChest, kNeckBase, kTrunkCoreRadius, "trunk"},
                          {kNeckBase, kHeadBase, kNeckCoreRadius, "neck"},
                          {kHeadBase, kHeadTop, kHeadCoreRadius, "head"}};
    struct Limb {
      int from, to;
      const char* name;
    };
    const Limb limbs[] = {{kLeftShoulder, kLeftElbow, "left upper arm"},
                          {kLeftElbow, kLeftWrist, "left forearm"},
                          {kRightShoulder, kRightElbow, "right upper arm"},
                          {kRightElbow, kRightWrist, "right forearm"}};
    for (const Limb& limb : limbs) {
      for (const Core& core : cores) {
        // The head core stops one radius below head_top, so that its surface ends at the crown
        // and a hand may rest on top of the head.
        Vector3d core_end = p[core.to];
        if (core.to == kHeadTop) {
          const Vector3d axis = p[kHeadTop] - p[kHeadBase];
          const double length = axis.norm();
          if (length > core.radius) core_end = p[kHeadTop] - axis * (core.radius / length);
        }
        const double distance = segment_distance(p[limb.from], p[limb.to], p[core.from], core_end);
        if (distance < core.radius) {
          log.add(std::string(limb.name) + core.name, f,
                  std::string(limb.name) + " passes through the " + core.name +
                      format(" (%.3f m from its axis, core radius %.3f m)", distance, core.radius));
        }
      }
    }
  }
  return log.result(frames.size());
}

}  // namespace wheelpose::motion
