#pragma once
// The built-in motion library: seated upper-body motions authored as keyframed joint angles in
// data/motions/*.yaml (format and angle conventions in data/motions/README.md). The YAML files
// are embedded into the binary at build time, so the library needs no files at run time.
// Each motion yields PositionClips that go through the normal pipeline like imported clips.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

struct LibraryMotionInfo {
  std::string id;
  std::string activity_class;
  std::string description;
};

// All built-in motions, sorted by id.
std::vector<LibraryMotionInfo> library_motions();

// One variant of a motion for a seed: speed x U(0.8,1.25), amplitude x U(0.85,1.1), mirrored
// with p=0.5 (all drawn from RandomStream(seed, {"library", id})). The clip is named "<id>",
// its source is "library:<id>" and its fps is the authored one. Unknown id throws Error.
PositionClip library_clip(const std::string& id, std::uint64_t seed);
// Every built-in motion for one seed, in library_motions() order.
std::vector<PositionClip> library_clips(std::uint64_t seed);

// ---- Lower level: parsing and synthesising one motion definition. ----

// One angle channel's keyframe track: (normalised time in [0, 1], degrees), times increasing.
struct ChannelTrack {
  std::vector<std::pair<double, double>> keys;
};

// A sinusoid added to a channel: amplitude * sin(2*pi*(cycles * t + phase)), t normalised,
// faded in and out over the window [start, end].
struct Oscillator {
  std::string channel;
  double amplitude = 0.0;  // degrees
  double cycles = 1.0;     // periods per clip
  double phase = 0.0;      // fraction of a period
  double start = 0.0;
  double end = 1.0;
};

struct MotionDefinition {
  std::string id;
  std::string activity_class;
  std::string description;
  double duration = 4.0;  // seconds at speed 1
  double fps = 30.0;
  bool loop = false;
  std::map<std::string, ChannelTrack> tracks;  // expanded channel names ("left_elbow_flexion")
  std::vector<Oscillator> oscillators;
};

struct MotionVariant {
  double speed = 1.0;      // > 1 plays faster (shorter clip)
  double amplitude = 1.0;  // scales each channel's excursion about the middle of its range
  bool mirrored = false;   // left and right exchanged (x -> -x)
};

// The activity classes of the paper's test set (Table "activity classes") plus the motions
// participants missed; every built-in motion's class is one of these.
const std::vector<std::string>& library_activity_classes();

// The channel names a motion file may use (after expanding "both_" and "trunk_" shorthands).
const std::vector<std::string>& motion_channel_names();

// Parses one motion file's text; `origin` names it in errors ("data/motions/clap.yaml").
// Malformed input throws Error naming origin, line and key.
MotionDefinition parse_motion_definition(const std::string& yaml_text, const std::string& origin);

// The channel values (degrees) of a definition at normalised time t for a variant's amplitude
// (mirroring is applied to positions, not here). Values are clamped to the channel limits.
std::map<std::string, double> motion_channels_at(const MotionDefinition& motion, double t,
                                                 double amplitude);

// The parsed definition of a built-in motion; unknown id throws Error.
const MotionDefinition& library_definition(const std::string& id);

// The variant library_clip() uses for (id, seed).
MotionVariant library_variant(const std::string& id, std::uint64_t seed);

// Renders a definition as joint positions: angles -> local rotations on the default skeleton ->
// forward_kinematics. Pelvis fixed at (0, 0.5, 0), legs seated (hips and knees at 90 degrees).
PositionClip synthesize_motion(const MotionDefinition& motion, const MotionVariant& variant);

// The same pose with left and right exchanged (reflection x -> -x).
Pose mirror_pose(const Pose& pose);

}  // namespace wheelpose::motion
