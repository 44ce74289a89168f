#pragma once
// Two contracts of Embree's 8-wide packet calls (rtcIntersect8, rtcOccluded8), each of which
// crashed the renderer on some CPUs:
// - The `valid` mask, like the rays, is read with aligned vector loads: both must start on a
//   32-byte boundary. Embree's AVX-512 kernels fault on a mask with less alignment (a plain
//   int[8] has 4), so the mask type carries the alignment itself, and an array or container of
//   masks keeps it for every element.
// - With only SSE4.2 Embree has no 8-wide kernel: it traces the packet as a ray stream, which
//   ignores the mask and skips only rays with tnear > tfar. Lanes left uninitialised were traced
//   (and tripped Embree's assertion on invalid rays), so every packet starts with every lane
//   switched off in the ray itself, and a lane is switched on by writing a whole ray into it.

#include <embree3/rtcore.h>

#include <array>
#include <limits>

namespace wheelpose::render {

struct alignas(32) PacketMask {
  std::array<int, 8> lanes{};  // −1: trace this lane, 0: skip it

  int& operator[](int lane) { return lanes[lane]; }
  int operator[](int lane) const { return lanes[lane]; }
  const int* data() const { return lanes.data(); }
  int count() const {
    int n = 0;
    for (int v : lanes) n += v != 0;
    return n;
  }
};

// Every lane finite and empty (tnear 0 > tfar −∞), which Embree's stream path skips.
inline void switch_off_lanes(RTCRay8& ray) {
  for (int k = 0; k < 8; ++k) {
    ray.org_x[k] = ray.org_y[k] = ray.org_z[k] = 0.0f;
    ray.dir_x[k] = ray.dir_y[k] = 0.0f;
    ray.dir_z[k] = 1.0f;
    ray.tnear[k] = 0.0f;
    ray.tfar[k] = -std::numeric_limits<float>::infinity();
    ray.time[k] = 0.0f;
    ray.mask[k] = 0;
    ray.id[k] = 0;
    ray.flags[k] = 0;
  }
}

static_assert(sizeof(PacketMask) == 32 && alignof(PacketMask) == 32);
static_assert(alignof(RTCRay8) >= 32 && alignof(RTCRayHit8) >= 32,
              "Embree's packet structs carry their own 32-byte alignment");

}  // namespace wheelpose::render
