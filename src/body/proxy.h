#pragma once
// MakeHuman proxies (`.mhclo` + `.obj`, CC0): clothes, shoes, hair and eyebrows that follow any
// body. Each proxy vertex is a barycentric blend of three base-mesh vertices plus an offset,
// scaled per axis by the body's size (x_scale/y_scale/z_scale: the distance between two base
// vertices over a reference). `delete_verts` lists the base vertices the proxy covers, which the
// body hides so skin does not poke through.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/random.h"

namespace wheelpose::body {

struct Proxy {
  std::string name;  // "<folder>/<name>", e.g. "clothes/shoes01"
  std::vector<std::array<int, 3>> refs;
  std::vector<Eigen::Vector3f> weights;
  std::vector<Eigen::Vector3f> offsets;  // base-mesh units (decimetres)
  std::array<std::array<float, 3>, 3> scales{};  // per axis: vertex a, vertex b, reference
  std::vector<int> delete_verts;
  std::vector<std::array<unsigned, 3>> triangles;  // over the proxy vertices
};

// Reads `<dir>/<name>.mhclo` and the `.obj` it names; throws Error naming file:line.
Proxy load_proxy(const std::filesystem::path& mhclo);

// The proxy's vertices on a body: `rest` and `posed` are the morphed base-mesh vertices
// (metres). The offset follows each reference triangle's frame from rest to pose.
std::vector<Eigen::Vector3f> fit_proxy(const Proxy& proxy, const std::vector<Eigen::Vector3f>& rest,
                                       const std::vector<Eigen::Vector3f>& posed);

// Every proxy under makehuman/<folder> (clothes, hair, eyebrows), as "<folder>/<name>", sorted.
std::vector<std::string> list_proxies(const std::filesystem::path& makehuman_root,
                                      const std::string& folder);

// The installed proxies by kind, each list sorted: suits by sex ("clothes/male_*",
// "clothes/female_*"), shoes (names holding "shoes"), hats (any other clothes), hair, eyebrows,
// eyes.
struct ProxyCatalog {
  std::vector<std::string> male_suits, female_suits, shoes, hats, hair, eyebrows, eyes;
  static ProxyCatalog scan(const std::filesystem::path& makehuman_root);
};

// One name of `from` chosen uniformly. One number is drawn even when `from` is empty, so the
// draws after it do not depend on what is installed.
std::string pick_proxy(RandomStream& rng, const std::vector<std::string>& from);

// A plausible outfit from what is installed: a suit for the sex (gender ≥ 0.5: male_*), shoes,
// hair (p = 0.85), eyebrows and the low-poly eyes; drawn from RandomStream(seed, {"outfit"}).
std::vector<std::string> sample_outfit(const std::filesystem::path& makehuman_root, double gender,
                                       std::uint64_t seed);

// Loads proxies by name on first use and keeps them (thread-safe).
class ProxyLibrary {
 public:
  explicit ProxyLibrary(std::filesystem::path makehuman_root) : root_(std::move(makehuman_root)) {}
  const Proxy& get(const std::string& name) const;

 private:
  std::filesystem::path root_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::unique_ptr<Proxy>> cache_;
};

}  // namespace wheelpose::body
