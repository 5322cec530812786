// Mitsuba 3 and mitransient XML scenes (docs/scene-format.md, "Mitsuba 3 XML"): the subset of
// plugins that maps onto vktg's scene, read strictly. Anything else (an unknown plugin, a property
// vktg does not read, a texture) is one vktg::Error "FILE:LINE: <element ...>: problem".
#pragma once
#include <filesystem>
#include <optional>

#include "scene/scan.h"
#include "vktg/scene.h"

namespace vktg {

struct MitsubaScene {
  Scene scene;
  // An nlos_capture_meter's grid of relay-wall points as a scan of the scene's point sensor (the
  // capture a render of the file gives); empty for a perspective sensor.
  std::optional<Scan> capture;
};

// Reads a Mitsuba XML scene; `defines` give its $name parameters (`-D name=value`), overriding the
// file's <default> values, and each must be used.
MitsubaScene loadMitsubaXml(const std::filesystem::path& path, const SceneDefines& defines);
// The scene alone (a capture's scene has its point sensor at the first grid point).
Scene loadMitsubaScene(const std::filesystem::path& path, const SceneDefines& defines);

// Whether the path names a Mitsuba XML file (by its extension, .xml in any case).
bool isMitsubaXmlPath(const std::filesystem::path& path);

}  // namespace vktg
