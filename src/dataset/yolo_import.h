#pragma once
// YOLO labels (one `<image stem>.txt` per image, one line per object: `class cx cy w h`
// normalised by the image size, optionally followed by K keypoints as `x y` or `x y v`) read
// into a COCO person file, so box-only real photo sets score with `eval --type bbox`.
//
// Each YOLO class is mapped to a role: the people to find (iscrowd 0), regions where a detection
// is neither rewarded nor punished (iscrowd 1), or dropped. A class without a role is an error,
// so a mapping never silently loses objects.

#include <filesystem>
#include <map>
#include <string>

#include "core/keypoint_template.h"
#include "dataset/coco_file.h"

namespace wheelpose::dataset {

enum class YoloRole { kPerson, kCrowd, kDrop };

// Parses "1=person,0=crowd,2=drop"; throws Error naming the bad item.
std::map<int, YoloRole> parse_yolo_classes(const std::string& text);

struct YoloImportOptions {
  std::filesystem::path images_dir;
  std::filesystem::path labels_dir;  // empty: the images folder
  std::map<int, YoloRole> classes;
  std::string description;  // info.description of the COCO file (e.g. the source's name)
};

// Every image of images_dir (.jpg/.jpeg/.png/.bmp, sorted by name, ids 1, 2, …) with the boxes of
// its label file (none if it has no label file: YOLO's background images). Annotations are
// numbered from 1 in (image, line) order; boxes are clipped to the image. Throws Error naming
// the file (and line) for a label without its image, a class outside the mapping, a short or
// long line, a value that is not a number, coordinates outside [0, 1] or an empty box.
json import_yolo(const YoloImportOptions& options, const KeypointTemplate& keypoint_template);

}  // namespace wheelpose::dataset
