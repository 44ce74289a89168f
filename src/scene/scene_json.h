#pragma once
// Scene ⇄ JSON. Every Scene value can be dumped and reloaded unchanged (floats are written with
// enough digits to round-trip). Errors name the file and the JSON path of the bad entry, e.g.
//   scene.json: /materials/2/texture/kind: unknown texture kind 'plaid' (none, image, noise, ...)

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "scene/scene.h"

namespace wheelpose::scene {

nlohmann::json scene_to_json(const Scene& scene);

// `origin` names the source in error messages (a file path or "<string>").
Scene scene_from_json(const nlohmann::json& j, const std::string& origin);

// Parses text; malformed JSON becomes an Error naming `origin`, the line and column.
Scene parse_scene(const std::string& text, const std::string& origin);

// Loads a file: relative texture/image paths are resolved against its directory, and referenced
// files must exist.
Scene load_scene(const std::filesystem::path& path);

std::string dump_scene(const Scene& scene);  // pretty-printed JSON text with a final newline

const char* texture_kind_name(TextureKind kind);

}  // namespace wheelpose::scene
