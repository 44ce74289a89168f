#pragma once
// A studio picture of one person in their wheelchair (for `wheelpose body sample`'s contact
// sheet): the person turned three-quarters to a camera in front of a grey wall, sunlit.

#include <opencv2/core.hpp>
#include <vector>

#include "body/person.h"

namespace wheelpose::generate {

// RGB, 8-bit, size × size pixels; `spp` samples per pixel. Deterministic for a spec.
cv::Mat render_portrait(const body::BodyData& data, const body::PersonSpec& spec, int size,
                        int spp = 4);

// Tiles equally sized RGB images into a grid, row by row (as square as possible).
cv::Mat contact_sheet(const std::vector<cv::Mat>& images);

}  // namespace wheelpose::generate
