// The figures `vktg optimize` draws of its targets every `images_every` iterations
// (docs/optimize.md, "Run directory"), chosen by what a target's image is:
//   - an image (more than one pixel): a strip of the target, the initial and the current render;
//   - a transient (one pixel, several time bins: a point sensor's bins gate): its three curves
//     against path length, since a tile of one pixel would show only their totals;
//   - the transients of a scan (two or more transient targets with the same gate): one figure with
//     every scan point's transient as a row (plot.h's writeTransientScan), so that a capture of a
//     thousand points is one picture. Scans of more than kMaxTransientPlots points get that figure
//     only, not one per point.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vktg/gate.h"
#include "vktg/image_io.h"

namespace vktg {

inline constexpr size_t kMaxTransientPlots = 16;

struct TargetImages {
  std::string name;
  Gate gate;  // the target's gate (its bins give the transient's path lengths)
  const ImageSet* target = nullptr;
  const ImageSet* initial = nullptr;
  const ImageSet* current = nullptr;
};

// Whether `image` is a transient: one pixel, several layers.
bool isTransient(const ImageSet& image);

// Writes the figures of `targets` at `iteration` into `directory`: <target>_<iteration>.png per
// target (as above), and transients/<iteration>.png for the first scan (two or more transient
// targets with one gate), transients/<iteration>_<k>.png for the k-th scan after it. Throws
// vktg::Error naming the file for a failed write or images that disagree in size.
void writeTargetFigures(const std::filesystem::path& directory, uint64_t iteration,
                        const std::vector<TargetImages>& targets);

}  // namespace vktg
