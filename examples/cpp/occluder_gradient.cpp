// Renders a scene, differentiates its image sum with respect to its first parameter forward (a
// derivative image) and backward (the adjoint pass with d loss / d I = 1 everywhere), and prints
// both: the two estimate one number, each with its own random numbers.
#include <cstdio>
#include <vktg/vktg.h>

int main(int argc, char** argv) {
  try {
    vktg::Context context;  // a GPU, else lavapipe
    vktg::Model model = argc > 1 ? vktg::Model::load(argv[1]) : vktg::Model::builtIn();
    if (model.parameterNames().empty()) {
      std::fprintf(stderr, "the scene has no parameters\n");
      return 2;
    }
    const std::string parameter = model.parameterNames().front();
    vktg::RenderRequest small;
    small.spp = 64;
    if (model.scene().camera.type == vktg::CameraType::Perspective) small.resolution = std::pair{32u, 32u};
    const vktg::Rendered image = vktg::render(context, model, small);
    double sum = 0;
    for (float v : image.images.front().layers.front().pixels) sum += v;

    vktg::GradRequest grad;
    static_cast<vktg::RenderRequest&>(grad) = small;
    const vktg::Derivatives forward = vktg::derivatives(context, model, {parameter}, grad);
    double forwardSum = 0;
    for (float v : forward.total.front().layers.front().pixels) forwardSum += v;

    vktg::ImageSet ones = image.images.front();
    for (vktg::ImageLayer& layer : ones.layers) layer.pixels.assign(layer.pixels.size(), 1.0f);
    grad.seed = 1;  // the adjoint pass's own random numbers
    const std::vector<double> backward = vktg::renderBackward(context, model, {parameter}, {ones}, grad);

    std::printf("%s: image sum %.6g; d sum / d %s: forward %.6g, backward %.6g\n", context.deviceName().c_str(), sum,
                parameter.c_str(), forwardSum, backward.front());
    return 0;
  } catch (const vktg::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
