// The terms of the time-gated derivative (docs/theory.md §3) as vktg runs them: one render each,
// one name each. The names are those of `vktg grad --terms` and `--split-terms`, the experiment
// file's budget.terms, the term pilot's table and the per-pass profile ("edge/shade").
#pragma once
#include <cstdint>

namespace vktg {

enum class Term : uint32_t {
  Interior,              // the image and, with derivatives, the interior term: per-pixel paths
  Edge,                  // the visibility boundary: edge samples, splatted where they reach the camera
  PathLength,            // the path-length boundary at the gate's jumps, from the paths' own vertices
  PathLengthFromCamera,  // its share behind a pinhole: connections from the camera, splatted
  InteriorAndPathLength, // adjoint renders only: Interior and PathLength from one trace of the paths
};

inline constexpr const char* termName(Term term) {
  switch (term) {
    case Term::Interior: return "interior";
    case Term::Edge: return "edge";
    case Term::PathLength: return "pathlength";
    case Term::PathLengthFromCamera: return "pathlength-camera";
    case Term::InteriorAndPathLength: return "interior+pathlength";
  }
  return "?";
}

}  // namespace vktg
