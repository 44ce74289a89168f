#pragma once
// The Scene value: everything the renderer and the annotator need to make one frame, as plain
// data (no handles, no caches), so it can be dumped to JSON, reloaded and compared.
//
// Units and axes follow ARCHITECTURE.md: metres, right-handed, +Y up, the camera looks down its
// own −Z. Angles are radians in code; the JSON form uses degrees (keys end in `_deg`).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace wheelpose::scene {

// A mesh built from a parametric description instead of explicit arrays. Kept beside the
// arrays so a dumped scene stays small (the arrays are regenerated on load).
struct PrimitiveSpec {
  std::string type;                                // "sphere", "box", "plane", "capsule"
  Eigen::Vector3f size = Eigen::Vector3f::Ones();  // sphere: radius = x; capsule: radius x,
                                                   // half-height of the cylinder y; plane: x,z
  int segments = 16;  // tessellation (sphere/capsule rings; plane/box subdivisions per side)
  bool operator==(const PrimitiveSpec&) const = default;
};

struct Mesh {
  std::string name;
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;    // per vertex, unit length; empty → flat face normals
  std::vector<Eigen::Vector2f> uvs;        // per vertex; empty → (0, 0)
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from the front
  // Per vertex, how far it travels while the shutter is open (metres, in the mesh's frame),
  // centred on the instant the positions show; empty → still. Drives motion blur.
  std::vector<Eigen::Vector3f> motion;
  std::optional<PrimitiveSpec> primitive;  // set when the arrays came from a primitive
  bool operator==(const Mesh&) const = default;
};

enum class TextureKind {
  kNone,
  kImage,
  kNoise,
  kStripes,
  kChecker,
  kFabric,
  kWood,
  kMarble,
  kImageDetail
};

// A colour pattern over UV space. Procedural kinds blend `color_a` (t = 0) and `color_b`
// (t = 1) with a pattern t(uv · scale); image textures multiply the material colour. An image
// detail texture keeps only a photo's brightness pattern (its luminance over its mean, so 1 on
// average), repeated `scale` times per UV unit, to multiply the material colour: a fabric
// photo's weave and folds in any garment colour.
struct Texture {
  TextureKind kind = TextureKind::kNone;
  // kImage, kImageDetail: any file OpenCV reads (relative paths from the scene file), or
  // "ARCHIVE!/ENTRY" for a file inside a zip (core/archive_member.h).
  std::string path;
  Eigen::Vector3f color_a = Eigen::Vector3f(0.8f, 0.8f, 0.8f);
  Eigen::Vector3f color_b = Eigen::Vector3f(0.2f, 0.2f, 0.2f);
  float scale = 8.0f;       // pattern repeats per UV unit
  float turbulence = 1.0f;  // noise amount for fabric/wood/marble
  std::uint64_t seed = 0;   // noise lattice seed
  bool operator==(const Texture&) const = default;
};

inline bool texture_has_image(TextureKind kind) {
  return kind == TextureKind::kImage || kind == TextureKind::kImageDetail;
}

struct Material {
  std::string name;
  Eigen::Vector3f diffuse = Eigen::Vector3f(0.8f, 0.8f, 0.8f);  // linear RGB albedo
  float specular = 0.0f;    // Blinn–Phong weight (0 = purely diffuse)
  float shininess = 32.0f;  // Blinn–Phong exponent
  Texture texture;
  float hue_offset_deg = 0.0f;  // the paper's HueOffsetRandomizer, applied after texturing
  // Alpha cards: MakeHuman's hair and eyebrows are layers of cards meant to be drawn with a
  // strand texture the assets lack. strands_per_uv > 0 draws strands running along the cards'
  // v, that many per UV unit across u, covering strand_coverage of the card; rays pass through
  // the rest (render/strands.h). 0 = an opaque surface.
  float strands_per_uv = 0.0f;
  float strand_coverage = 0.7f;
  bool operator==(const Material&) const = default;
};

// Labels: instance_id 0 and semantic_id 0 mean "background / unlabelled" in the id buffers.
struct Instance {
  std::string name;
  int mesh = 0;                                             // index into Scene::meshes
  int material = 0;                                         // index into Scene::materials
  Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();  // object → world (affine)
  std::uint16_t instance_id = 0;
  std::uint16_t semantic_id = 0;
  bool operator==(const Instance&) const = default;
};

// Solar position (see solar_direction()): the paper's SunAngleRandomizer samples these three.
struct SolarPosition {
  float hour = 12.0f;          // local solar time, 0–24
  float day_of_year = 172.0f;  // 0–365
  float latitude_deg = 0.0f;   // −90 (south pole) … 90 (north pole)
  bool operator==(const SolarPosition&) const = default;
};

struct Sun {
  bool enabled = true;
  // Unit vector from the scene toward the sun (world). Ignored when `solar` is set.
  Eigen::Vector3f direction = Eigen::Vector3f(0.3f, 1.0f, 0.5f).normalized();
  std::optional<SolarPosition> solar;
  Eigen::Vector3f color = Eigen::Vector3f(1.0f, 0.957f, 0.839f);  // the authors' sun colour
  float intensity = 1.0f;  // irradiance on a surface facing the sun; 1 → white diffuse = 1.0
  float angular_radius_deg = 0.5f;  // > 0 gives soft shadows (the real sun: 0.27°)
  bool operator==(const Sun&) const = default;
};

struct PointLight {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Vector3f color = Eigen::Vector3f::Ones();
  float intensity = 1.0f;  // radiant intensity: irradiance at 1 m facing the light
  float radius = 0.05f;    // sphere light radius for soft shadows (0 = hard)
  bool on = true;
  bool operator==(const PointLight&) const = default;
};

struct Environment {
  std::string path;  // equirectangular image (HDR or LDR), empty = uniform `color`
  Eigen::Vector3f color = Eigen::Vector3f(0.05f, 0.05f, 0.06f);  // uniform sky radiance
  float intensity = 1.0f;
  float rotation_deg = 0.0f;  // about +Y
  bool operator==(const Environment&) const = default;
};

// The vertical field of view drives projection. When `focal_length_mm` > 0 it overrides the FOV
// through the sensor height: vfov = 2·atan(sensor_height_mm / (2·focal_length_mm)). Depth of
// field is a thin lens of radius `aperture_radius` (metres, 0 = pinhole) focused at
// `focus_distance` (metres along the view axis).
struct Camera {
  Eigen::Vector3f position = Eigen::Vector3f(0.0f, 0.0f, 5.0f);
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();  // camera → world
  float vfov_deg = 60.0f;
  float focal_length_mm = 0.0f;
  float sensor_height_mm = 24.0f;
  float aperture_radius = 0.0f;
  float focus_distance = 10.0f;
  int width = 1280;
  int height = 720;
  bool operator==(const Camera& o) const {
    return position == o.position && orientation.coeffs() == o.orientation.coeffs() &&
           vfov_deg == o.vfov_deg && focal_length_mm == o.focal_length_mm &&
           sensor_height_mm == o.sensor_height_mm && aperture_radius == o.aperture_radius &&
           focus_distance == o.focus_distance && width == o.width && height == o.height;
  }
  // The vertical field of view actually used, in radians.
  float effective_vfov() const;
};

// Post-processing on the linear image, in this order: lens blur, exposure (automatic, then the
// compensation), white balance, sensor noise, bloom, contrast, saturation, vignette, tone curve
// (clip or filmic), sRGB encoding, film grain. Neutral values are the defaults; ranges follow the
// paper's PostProcessVolumeRandomizer (Unity HDRP units) where it has them.
struct PostProcess {
  float exposure_ev = 0.0f;  // multiply by 2^ev
  float temperature = 0.0f;  // −100 … 100; positive = warmer (more red, less blue)
  float contrast = 0.0f;     // −100 … 100, pivot at mid grey 0.18
  float saturation = 0.0f;   // −100 (grey) … 100
  float vignette = 0.0f;     // 0 … 1: corner darkening
  float bloom = 0.0f;        // 0 … 1: glow added around pixels above `bloom_threshold`
  float bloom_threshold = 1.0f;
  float film_grain = 0.0f;  // 0 … 1: seeded noise (one stream per image row)
  float lens_blur = 0.0f;   // max blur radius in pixels for depth away from the focus
  // A camera's automatic exposure: > 0 scales the image so that its log-average luminance
  // becomes this key (0.18 = mid grey); 0 = off (the light units decide).
  float auto_exposure_key = 0.0f;
  // Sensor noise in linear units of the sensor's signal s, before the exposure gain g: variance
  // shot_noise · s + read_noise², so after the gain g · shot_noise · x + (g · read_noise)² —
  // dark scenes that the exposure lifts get grainier, as in a phone's photos.
  float shot_noise = 0.0f;
  float read_noise = 0.0f;
  bool filmic = false;  // a filmic shoulder (the ACES fit of Narkowicz 2015) instead of clipping
  bool operator==(const PostProcess&) const = default;
};

// What primary rays that miss everything see. An image is scaled to cover the frame keeping its
// aspect ratio (centre crop, never stretched); a texture is evaluated in screen UV with square
// cells; otherwise the environment (if it has a map) or `color`.
struct Background {
  Eigen::Vector3f color = Eigen::Vector3f(0.1f, 0.1f, 0.12f);
  Texture texture;
  std::string image;
  bool operator==(const Background&) const = default;
};

struct Scene {
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Instance> instances;
  Sun sun;
  std::vector<PointLight> point_lights;
  std::optional<Environment> environment;
  Camera camera;
  PostProcess post;
  Background background;
  std::uint64_t seed = 0;  // sampling seed of this frame
  // Directory that relative texture/image paths are resolved against (not serialised).
  std::string base_dir;
  bool operator==(const Scene& o) const {
    return meshes == o.meshes && materials == o.materials && instances == o.instances &&
           sun == o.sun && point_lights == o.point_lights && environment == o.environment &&
           camera == o.camera && post == o.post && background == o.background && seed == o.seed;
  }
};

// Unit vector toward the sun for a solar position, in the world frame (+Y up, north = −Z,
// east = +X). See scene.cpp for the formulas. Below the horizon the vector points down.
Eigen::Vector3f solar_direction(const SolarPosition& s);

// The sun direction actually used (explicit or from the solar model).
Eigen::Vector3f sun_direction(const Sun& sun);

// Resolves a path from the scene against its base directory.
std::string resolve_path(const Scene& scene, const std::string& path);

}  // namespace wheelpose::scene
