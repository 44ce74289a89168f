// Labels from ground truth: projected keypoints with depth-buffer visibility, visible masks
// (box, area, polygons) from the instance buffer, amodal boxes from rasterised silhouettes.

#include "generate/labeler.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "scene/projector.h"

namespace wheelpose::generate {
namespace {

using Eigen::Vector3f;

// Rounds to `digits` decimals; dividing by an exact power of ten gives the double nearest the
// decimal, so JSON prints it short ("12.345", not "12.345000000000001").
double round_to(double v, int digits) {
  const double scale = std::pow(10.0, digits);
  return std::round(v * scale) / scale;
}

using scene::Projector;

constexpr float kNear = 1e-3f;

// The person's silhouette with nothing in front of it, and the camera-space box of its body.
struct Amodal {
  cv::Mat mask;  // CV_8U
  Eigen::AlignedBox3f box;
};

Amodal amodal_silhouette(const scene::Scene& scene, std::uint16_t id, const Projector& proj) {
  Amodal out;
  out.mask = cv::Mat::zeros(proj.height, proj.width, CV_8U);
  for (const scene::Instance& inst : scene.instances) {
    if (inst.instance_id != id) continue;
    const scene::Mesh& mesh = scene.meshes[static_cast<std::size_t>(inst.mesh)];
    std::vector<Vector3f> cam(mesh.positions.size());
    for (std::size_t v = 0; v < cam.size(); ++v) {
      const Vector3f world = (inst.transform * mesh.positions[v].homogeneous()).head<3>();
      cam[v] = proj.to_camera(world);
      out.box.extend(cam[v]);
    }
    std::vector<cv::Point> poly(3);
    for (const Eigen::Vector3i& t : mesh.triangles) {
      bool in_front = true;
      for (int c = 0; c < 3; ++c) {
        const Vector3f& p = cam[static_cast<std::size_t>(t[c])];
        if (p.z() > -kNear) {
          in_front = false;
          break;
        }
        const Eigen::Vector2f px = proj.project(p);
        // 4 fractional bits keep sub-pixel accuracy in fillConvexPoly.
        poly[c] = cv::Point(static_cast<int>(std::lround(std::clamp(px.x(), -1e5f, 1e5f) * 16)),
                            static_cast<int>(std::lround(std::clamp(px.y(), -1e5f, 1e5f) * 16)));
      }
      if (in_front) cv::fillConvexPoly(out.mask, poly, cv::Scalar(255), cv::LINE_8, 4);
    }
  }
  return out;
}

nlohmann::ordered_json box_json(const cv::Rect& r) {
  return nlohmann::ordered_json::array({r.x, r.y, r.width, r.height});
}

nlohmann::ordered_json polygons(const cv::Mat& mask) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const auto& contour : contours) {
    nlohmann::ordered_json poly = nlohmann::ordered_json::array();
    if (contour.size() >= 3) {
      for (const cv::Point& p : contour) {
        poly.push_back(p.x);
        poly.push_back(p.y);
      }
    } else {  // a one- or two-pixel sliver: its bounding square
      const cv::Rect r = cv::boundingRect(contour);
      for (const cv::Point& p :
           {r.tl(), cv::Point(r.x + r.width, r.y), r.br(), cv::Point(r.x, r.y + r.height)}) {
        poly.push_back(p.x);
        poly.push_back(p.y);
      }
    }
    out.push_back(std::move(poly));
  }
  return out;
}

}  // namespace

Eigen::Matrix4f camera_to_world(const scene::Camera& camera) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.topLeftCorner<3, 3>() = camera.orientation.normalized().toRotationMatrix();
  m.topRightCorner<3, 1>() = camera.position;
  return m;
}

FrameLabels label_frame(const BuiltFrame& frame, const render::FrameBuffers& buffers,
                        const LabelOptions& options) {
  const scene::Camera& cam = frame.scene.camera;
  const Projector proj(cam);
  FrameLabels labels;
  nlohmann::ordered_json camera;
  camera["intrinsics"] = {
      {"fx", round_to(proj.f, 4)}, {"fy", round_to(proj.f, 4)}, {"cx", proj.cx}, {"cy", proj.cy}};
  camera["vfov_deg"] = round_to(cam.effective_vfov() * 180.0 / M_PI, 5);
  const Eigen::Matrix4f extrinsics = camera_to_world(cam);
  nlohmann::ordered_json e = nlohmann::ordered_json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) e.push_back(round_to(extrinsics(r, c), 7));
  camera["extrinsics"] = std::move(e);
  labels.image["width"] = cam.width;
  labels.image["height"] = cam.height;
  labels.image["camera"] = std::move(camera);

  for (const LabelPerson& person : frame.people) {
    cv::Mat mask = buffers.instance == static_cast<double>(person.instance_id);  // CV_8U 0/255
    const int pixels = cv::countNonZero(mask);
    if (pixels < options.min_visible_pixels || pixels == 0) {
      ++labels.dropped_people;
      continue;
    }
    const Amodal amodal = amodal_silhouette(frame.scene, person.instance_id, proj);
    cv::Rect box = cv::boundingRect(mask);
    nlohmann::ordered_json kp = nlohmann::ordered_json::array();
    nlohmann::ordered_json kp3 = nlohmann::ordered_json::array();
    int labelled = 0;
    for (std::size_t k = 0; k < person.keypoints.size(); ++k) {
      const Vector3f c = proj.to_camera(person.keypoints[k]);
      int v = 0;
      Eigen::Vector2f px(0, 0);
      if (person.present[k] && c.z() < -kNear) {
        px = proj.project(c);
        const int ix = static_cast<int>(std::floor(px.x())),
                  iy = static_cast<int>(std::floor(px.y()));
        if (ix >= 0 && iy >= 0 && ix < cam.width && iy < cam.height) {
          const float depth = buffers.depth.at<float>(iy, ix);
          v = depth > 0 && depth < -c.z() - person.tolerance[k] ? 1 : 2;
          if (v == 2) box |= cv::Rect(ix, iy, 1, 1);
        }
      }
      if (v == 0) {
        kp.insert(kp.end(), {0, 0, 0});
      } else {
        ++labelled;
        kp.insert(kp.end(), {round_to(px.x(), 3), round_to(px.y(), 3), v});
      }
      if (person.present[k]) {
        kp3.insert(kp3.end(), {round_to(c.x(), 5), round_to(c.y(), 5), round_to(c.z(), 5)});
      } else {
        kp3.insert(kp3.end(), {0, 0, 0});
      }
    }
    const int amodal_pixels = cv::countNonZero(amodal.mask);
    nlohmann::ordered_json a;
    a["category_id"] = 1;
    a["iscrowd"] = 0;
    cv::Rect held = box;
    bool seated = false;
    if (options.box_holds_wheelchair) {
      const cv::Mat chair =
          buffers.instance == static_cast<double>(kChairIdBase + person.instance_id);
      seated = cv::countNonZero(chair) > 0;
      if (seated) held |= cv::boundingRect(chair);
    }
    a["bbox"] = box_json(held);
    if (seated) a["bbox_person"] = box_json(box);
    a["area"] = pixels;
    if (options.segmentation) a["segmentation"] = polygons(mask);
    a["num_keypoints"] = labelled;
    a["keypoints"] = std::move(kp);
    a["instance_id"] = person.instance_id;  // the person's value in the instance map
    a["bbox_amodal"] = box_json(amodal_pixels > 0 ? cv::boundingRect(amodal.mask) | box : box);
    a["visible_fraction"] =
        round_to(std::min(1.0, static_cast<double>(pixels) / std::max(amodal_pixels, pixels)), 4);
    a["keypoints_3d"] = std::move(kp3);
    const Vector3f lo = amodal.box.min(), hi = amodal.box.max();
    a["bbox_3d"] = {round_to(lo.x(), 4), round_to(lo.y(), 4), round_to(lo.z(), 4),
                    round_to(hi.x(), 4), round_to(hi.y(), 4), round_to(hi.z(), 4)};
    for (const auto& [key, value] : person.attributes.items()) a[key] = value;
    labels.annotations.push_back(std::move(a));
  }
  return labels;
}

}  // namespace wheelpose::generate
