#pragma once
// Animated GIF preview of a clip's joint positions, after the authors' visualisation (four views
// of the skeleton: oblique from above, front, top, side), so a motion can be checked at a glance.
//
// Layout (2×2 panels of view_size pixels): top-left 45° oblique from above the subject's
// front-left, top-right front view (the subject faces the viewer, so its left is on the right),
// bottom-left top view (front towards the bottom of the panel), bottom-right side view from the
// subject's right (the subject faces right). Orthographic projection with one scale for the whole
// clip, so the figure never jumps; a grey floor grid at the lowest joint height. The subject's left
// side is blue, its right side red, the centre line black; joints are dots.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "motion/clip.h"

namespace wheelpose::motion {

struct PreviewOptions {
  int view_size = 256;  // pixels per panel side; the GIF is 2·view_size square
  double fps = 0;       // playback rate; 0 = the clip's fps
};

// The fixed palette (index → RGB) every preview GIF uses.
enum PreviewColour : std::uint8_t {
  kPreviewBackground = 0,  // white
  kPreviewCentre = 1,      // black
  kPreviewLeft = 2,        // blue
  kPreviewRight = 3,       // red
  kPreviewFloor = 4,       // light grey
  kPreviewText = 5,        // mid grey
  kPreviewLeftJoint = 6,   // dark blue
  kPreviewRightJoint = 7,  // dark red
};
inline constexpr int kPreviewPaletteSize = 8;
const std::array<std::array<std::uint8_t, 3>, kPreviewPaletteSize>& preview_palette();

// Renders the frames as palette indices (one 2·view_size square image per frame, row-major).
std::vector<std::vector<std::uint8_t>> render_preview_frames(const std::vector<Pose>& positions,
                                                             int view_size);

// Writes a looping GIF; frame delay = round(100 / fps) centiseconds (at least 2, the smallest
// delay browsers honour). Throws Error on empty or non-finite input and on I/O failure.
void write_preview_gif(const std::vector<Pose>& positions, double fps,
                       const std::filesystem::path& path, const PreviewOptions& options = {});

}  // namespace wheelpose::motion
