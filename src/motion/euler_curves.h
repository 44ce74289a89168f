#pragma once
// Rotation keys as Euler angle curves for formats that animate angles (FBX): the angles of each
// key are the equivalent set nearest the previous key's (the other of the two Tait-Bryan
// solutions, ±360° per angle), so no angle jumps across ±180° between keys and a reader that
// interpolates the angles linearly turns the short way. The rotation order is chosen per
// joint so that this linear interpolation stays closest to the spherical one.

#include <Eigen/Geometry>
#include <vector>

namespace wheelpose::motion {

// FBX's RotationOrder enum: the axes in the order they are applied, so kXYZ is R = Rz·Ry·Rx.
enum class EulerOrder : int { kXYZ = 0, kXZY = 1, kYZX = 2, kYXZ = 3, kZXY = 4, kZYX = 5 };

// The rotation of angles (radians about X, Y, Z) applied in `order`.
Eigen::Quaterniond euler_rotation(const Eigen::Vector3d& angles, EulerOrder order);

// Angles (radians about X, Y, Z) of `rotations` in `order`, continuous from key to key; the
// first key has its middle angle in [-90°, 90°] and every angle in (-180°, 180°].
std::vector<Eigen::Vector3d> continuous_euler(const std::vector<Eigen::Quaterniond>& rotations,
                                              EulerOrder order);

// Largest angle (radians) between the rotation that linear interpolation of `curves` gives
// halfway between two keys and the spherical interpolation of `rotations` there.
double halfway_error(const std::vector<Eigen::Quaterniond>& rotations,
                     const std::vector<Eigen::Vector3d>& curves, EulerOrder order);

// The order with the smallest halfway_error (the first of equals, from kXYZ on).
EulerOrder best_euler_order(const std::vector<Eigen::Quaterniond>& rotations);

}  // namespace wheelpose::motion
