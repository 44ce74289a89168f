#pragma once
// Helpers of the motion exporters' tests, defined in export_gltf_test.cpp and shared by the other
// export tests of the same test executable.

#include <assimp/scene.h>

#include <filesystem>
#include <string>

#include "motion/clip.h"

namespace wheelpose::motion::export_test {

// A hand-made motion on the T-pose skeleton (root moving and rising, elbow, shoulder, spine and
// pelvis turning): every exporter must reproduce it.
SkeletalMotion make_test_motion(int frames, double fps);
// World positions of the nodes named like our joints at `seconds` into the scene's first
// animation (linear interpolation between keys).
Pose scene_joint_positions(const aiScene& scene, double seconds);
void expect_plays_like(const aiScene& scene, const SkeletalMotion& motion, double tolerance);
double ticks_per_second(const aiAnimation& animation);
std::filesystem::path temp_dir(const std::string& name);

}  // namespace wheelpose::motion::export_test
