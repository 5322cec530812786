// Image losses of `vktg optimize` and their adjoint images (the per-pixel derivative the gradient
// passes weight every sample with, THEORY.md §7). Sums over pixels and layers are divided by their
// count, so a loss does not scale with resolution or stack length.
#pragma once
#include "opt/experiment.h"
#include "vktg/image_io.h"

namespace vktg {

// weight * mean over pixels and layers of:
//   L2           (I - T)^2
//   L1           |I - T|                     (derivative sign(I - T), 0 at I = T)
//   RelativeL2   (I - T)^2 / (T^2 + (epsilon * mean|T|)^2)
// `adjoint`, when given, receives d loss / d I with the layout of `rendered`. Throws vktg::Error
// when the two images differ in size or layers.
double imageLoss(const LossSpec& spec, const ImageSet& rendered, const ImageSet& target, double weight,
                 ImageSet* adjoint = nullptr);

}  // namespace vktg
