// The room the loss-gradient tests share (tests/optimize_*.cpp).
#pragma once
#include "vktg/scene.h"

namespace vktg::test {

// A floor (diffuse), a glossy block hovering over it, an area light and a point light, seen by a
// 12 x 12 pinhole under a box gate: interior, edge (the block's silhouette and shadow) and
// path-length-boundary terms, and a parameter of every kind.
inline Scene roomScene() {
  return parseSceneJson(R"({
    "version": 1,
    "camera": {"type": "perspective", "position": [0, 1.2, 3], "look_at": [0, 0.2, 0], "fov_y": 40, "resolution": [12, 12]},
    "gate": {"type": "box", "a": 5.2, "b": 6.4},
    "materials": {"floor": {"type": "diffuse", "albedo": 0.6},
                  "metal": {"type": "conductor", "albedo": 0.8, "roughness": 0.35}},
    "shapes": [
      {"name": "floor", "type": "rectangle", "material": "floor", "transform": {"rotate": [-90, 0, 0], "scale": 2}},
      {"name": "block", "type": "cube", "material": "metal",
       "transform": {"translate": [0.1, 0.45, 0], "rotate": [0, 25, 0], "scale": 0.25}},
      {"name": "lamp", "type": "rectangle", "emission": 8,
       "transform": {"translate": [0.3, 1.6, 0.2], "rotate": [90, 0, 0], "scale": 0.3}}
    ],
    "lights": [{"type": "point", "name": "bulb", "position": [-0.8, 1.0, 0.6], "intensity": 1.5}],
    "parameters": [
      {"name": "block_x", "type": "translate", "shape": "block", "axis": [1, 0, 0]},
      {"name": "bulb_y", "type": "light_position", "light": "bulb", "axis": [0, 1, 0]},
      {"name": "floor_albedo", "type": "albedo", "material": "floor"},
      {"name": "t0", "type": "gate_center"},
      {"name": "spin", "type": "rotate", "shape": "block", "axis": [0, 1, 0]},
      {"name": "gloss", "type": "roughness", "material": "metal"},
      {"name": "lamp_power", "type": "emission", "shape": "lamp"},
      {"name": "bulb_power", "type": "intensity", "light": "bulb"}
    ],
    "render": {"spp": 16, "max_depth": 4, "seed": 3}
  })", "room.json", ".");
}

}  // namespace vktg::test
