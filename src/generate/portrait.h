#pragma once
// A studio picture of one person in their wheelchair, for `wheelpose body sample`'s contact
// sheet (tiled by dataset::ContactSheet): the person turned three-quarters to a camera in front
// of a grey wall, sunlit.

#include <opencv2/core.hpp>

#include "body/person.h"

namespace wheelpose::generate {

// RGB, 8-bit, size × size pixels; `spp` samples per pixel. Deterministic for a spec.
cv::Mat render_portrait(const body::BodyData& data, const body::PersonSpec& spec, int size,
                        int spp = 4);

}  // namespace wheelpose::generate
