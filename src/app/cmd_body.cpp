// `wheelpose body`: parametric people (MakeHuman CC0 data) seated in fitted wheelchairs and
// posed by seated clips, written as glb for inspection, with a parameters/keypoints JSON.

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "body/assets.h"
#include "body/person.h"
#include "body/person_animation.h"
#include "body/person_glb.h"
#include "body/rigged_fbx.h"
#include "body/rigged_glb.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "dataset/coco_viz.h"
#include "generate/portrait.h"
#include "motion/clip_json.h"
#include "render/frame_io.h"

namespace wheelpose::app {
namespace {

namespace fs = std::filesystem;

struct BodyOptions {
  std::string assets;
  std::uint64_t seed = 0;
  std::vector<std::string> params;
  std::string clip;
  int frame = 0;
  std::string out;
  int count = 1;
  bool empty = false;
  bool cc_by = false;
  bool rigged = false;
  std::string portrait;  // PNG of the exported person in our renderer
};

fs::path json_beside(const fs::path& glb) {
  fs::path json = glb;
  json.replace_extension(".json");
  return json;
}

std::optional<fs::path> explicit_assets(const BodyOptions& o) {
  if (o.assets.empty()) return std::nullopt;
  return fs::path(o.assets);
}

void write_person(const body::BodyData& data, const body::PersonSpec& spec, const fs::path& out) {
  const body::Person person = body::build_person(data, spec);
  body::write_person_glb(person, data, out);
  write_file_atomic(json_beside(out), person.description.dump(2) + "\n");
}

void run_export(const BodyOptions& o) {
  if (o.out.empty()) throw Error("body export: --out is required");
  body::PersonSpec spec = body::sample_spec(o.seed);
  body::apply_overrides(spec, o.params);
  if (o.rigged && (o.cc_by || o.empty))
    throw Error(
        "body export: --rigged exports a person, not --empty-wheelchair or --cc-by-wheelchair");
  if (!o.portrait.empty() && (o.rigged || o.cc_by || o.empty))
    throw Error(
        "body export: --portrait renders a posed person, not --rigged or a wheelchair alone");
  if (o.cc_by) {
    body::write_cc_by_wheelchair_glb(o.out);
    spdlog::info("wrote {} (credit: {})", o.out, body::kCcByWheelchairCredit);
    return;
  }
  if (o.empty) {
    if (spec.wheelchair == body::WheelchairType::kNone)
      throw Error("body export: --empty-wheelchair with wheelchair=none leaves nothing to export");
    RandomStream stream(o.seed, {"body", "wheelchair"});
    const body::Wheelchair chair = body::make_empty_wheelchair(spec.wheelchair, stream);
    body::write_wheelchair_glb(chair, o.out);
    write_file_atomic(json_beside(o.out), chair.dimensions.dump(2) + "\n");
    spdlog::info("wrote empty {} wheelchair to {}", body::wheelchair_type_name(spec.wheelchair),
                 o.out);
    return;
  }
  if (o.rigged) {
    if (o.clip.empty()) throw Error("body export: --rigged needs --clip (the motion to animate)");
    const std::string extension = fs::path(o.out).extension().string();
    if (extension != ".glb" && extension != ".fbx")
      throw Error("body export: --rigged --out " + o.out +
                  ": the file name must end in .glb or .fbx (the format written)");
    const motion::SeatedClip clip = motion::read_seated_clip_json(o.clip);
    const body::BodyData data(body::locate_assets(explicit_assets(o)));
    const body::PersonAnimation animation = body::animate_person(data, spec, clip.motion);
    if (extension == ".fbx") {
      body::write_rigged_person_fbx(animation, data, o.out);
    } else {
      body::write_rigged_person_glb(animation, data, o.out);
    }
    write_file_atomic(json_beside(o.out), animation.person.description.dump(2) + "\n");
    spdlog::info("wrote {} ({} frames) and {}", o.out, animation.frames.size(),
                 json_beside(o.out).string());
    return;
  }
  if (!o.clip.empty()) {
    const motion::SeatedClip clip = motion::read_seated_clip_json(o.clip);
    if (o.frame < 0 || static_cast<std::size_t>(o.frame) >= clip.motion.frame_count()) {
      throw Error(o.clip + ": --frame " + std::to_string(o.frame) + " out of range (clip has " +
                  std::to_string(clip.motion.frame_count()) + " frames)");
    }
    spec.pose = motion::global_rotations(clip.motion, static_cast<std::size_t>(o.frame));
  }
  const body::BodyData data(body::locate_assets(explicit_assets(o)));
  write_person(data, spec, o.out);
  spdlog::info("wrote {} and {}", o.out, json_beside(o.out).string());
  if (!o.portrait.empty()) {
    constexpr int kPortraitSize = 512, kPortraitSpp = 16;
    write_file_atomic(o.portrait, render::encode_png(generate::render_portrait(
                                      data, spec, kPortraitSize, kPortraitSpp)));
    spdlog::info("wrote {}", o.portrait);
  }
}

void run_sample(const BodyOptions& o) {
  if (o.out.empty()) throw Error("body sample: --out is required");
  if (o.count < 1) throw Error("body sample: --count must be at least 1");
  const body::BodyData data(body::locate_assets(explicit_assets(o)));
  ensure_directory(o.out);
  dataset::ContactSheet sheet(static_cast<std::size_t>(o.count), cv::Size(256, 256));
  for (int i = 0; i < o.count; ++i) {
    // Person i of seed S is the person of seed RandomStream(S, {"body_sample", i}).
    RandomStream stream(o.seed, {"body_sample", i});
    body::PersonSpec spec = body::sample_spec(stream.next_u64());
    spec.proxies = body::sample_outfit(data.model().root(), spec.params.gender, spec.seed);
    body::apply_overrides(spec, o.params);
    char name[32];
    std::snprintf(name, sizeof(name), "person_%04d.glb", i);
    write_person(data, spec, fs::path(o.out) / name);
    sheet.place(static_cast<std::size_t>(i), generate::render_portrait(data, spec, 256));
  }
  write_file_atomic(fs::path(o.out) / "contact_sheet.png", render::encode_png(sheet.image()));
  spdlog::info("wrote {} people and contact_sheet.png to {}", o.count, o.out);
}

}  // namespace

void attach_body(CLI::App& parent) {
  CLI::App* cmd = parent.add_subcommand(
      "body", "Parametric people seated in fitted wheelchairs (MakeHuman CC0 data)");
  cmd->require_subcommand(1);
  auto options = std::make_shared<BodyOptions>();
  auto common = [&](CLI::App* sub) {
    sub->add_option("--seed", options->seed, "Random seed (person and wheelchair)");
    sub->add_option("--params", options->params,
                    "Overrides k=v: gender, age, muscle, weight, height, proportions, african, "
                    "asian, caucasian, skin_tone, wheelchair=manual|sport|power, "
                    "left_leg/right_leg=none|below_knee|above_knee, "
                    "left_arm/right_arm=none|below_elbow|above_elbow, "
                    "mobility_aid=none|cane|crutches|walker, "
                    "wear=clothes/<name>|hair/<name>|eyebrows/<name> (repeatable)");
    sub->add_option("--assets", options->assets, "Asset root holding makehuman/");
    sub->add_option("--out", options->out, "Output")->required();
  };
  CLI::App* exp = cmd->add_subcommand("export", "One posed person in a wheelchair as glb");
  common(exp);
  exp->add_option("--clip", options->clip, "Seated clip JSON (wheelpose motion output)");
  CLI::Option* frame = exp->add_option("--frame", options->frame, "Frame of the clip");
  exp->add_flag("--rigged", options->rigged,
                "Skinned to the rig and animated by the whole --clip (joints, skin weights and "
                "the clip as an animation; glb or binary FBX by --out's extension)")
      ->excludes(frame);
  exp->add_option("--portrait", options->portrait,
                  "Also render the person with our ray tracer (512² PNG, as `body sample`'s "
                  "contact sheet)");
  exp->add_flag("--empty-wheelchair", options->empty, "Only the wheelchair, nobody in it");
  exp->add_flag("--cc-by-wheelchair", options->cc_by,
                "Only the CC-BY \"Wheel Chair\" by bgamage (sweethome3d-furniture)");
  exp->callback([options] { run_export(*options); });
  CLI::App* sample = cmd->add_subcommand("sample", "N random people, glb + JSON each");
  common(sample);
  sample->add_option("--count", options->count, "How many people")->required();
  sample->callback([options] { run_sample(*options); });
}

}  // namespace wheelpose::app
