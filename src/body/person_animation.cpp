#include "body/person_animation.h"

#include <tbb/parallel_for.h>

#include "motion/stick_figure.h"

namespace wheelpose::body {

PersonAnimation animate_person(const BodyData& data, PersonSpec spec,
                               const motion::SkeletalMotion& clip) {
  motion::check_exportable(clip, "rigged glTF");
  PersonAnimation out;
  out.name = clip.name;
  out.fps = clip.fps;
  spec.pose = motion::global_rotations(clip, 0);
  out.person = build_person(data, spec);
  out.frames.resize(clip.frame_count());
  out.frames[0] = out.person.pose;
  // Frames are independent and each lands in its own slot, so the result does not depend on
  // the thread count.
  tbb::parallel_for(std::size_t{1}, clip.frame_count(), [&](std::size_t f) {
    PersonSpec at_frame = spec;
    at_frame.pose = motion::global_rotations(clip, f);
    out.frames[f] = build_person(data, at_frame).pose;
  });
  return out;
}

}  // namespace wheelpose::body
