// vktg._vktg: the C++ API (vktg/vktg.h) for Python, kept thin: python/vktg/__init__.py gives it
// its Python shape (keyword arguments, checks of arrays, gates as objects). Images cross as NumPy
// float32 arrays of shape (height, width, layers), the layout of `vktg render --npy`: an output is
// one copy out of the renderer's per-layer images into the array NumPy then owns; an input is read
// in place. Every render releases the GIL; between batches it takes the GIL back to check for
// Ctrl-C (which stops the render as SIGINT stops the command line: KeyboardInterrupt) and to call
// the caller's progress function.
#include <csignal>
#include <memory>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/function.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <vktg/vktg.h>

namespace nb = nanobind;
using Array = nb::ndarray<nb::numpy, float>;
using InputArray = nb::ndarray<const float, nb::ndim<3>, nb::c_contig, nb::device::cpu>;

namespace {

// (height, width, layers) float32, owning its data.
Array toArray(const vktg::ImageSet& image) {
  const size_t h = image.height, w = image.width, layers = image.layers.size();
  auto* data = new std::vector<float>(h * w * layers);
  for (size_t l = 0; l < layers; ++l) {
    const std::vector<float>& pixels = image.layers[l].pixels;
    for (size_t i = 0; i < h * w; ++i) (*data)[i * layers + l] = pixels[i];
  }
  nb::capsule owner(data, [](void* p) noexcept { delete static_cast<std::vector<float>*>(p); });
  const size_t shape[3] = {h, w, layers};
  return Array(data->data(), 3, shape, owner);
}

std::vector<Array> toArrays(const std::vector<vktg::ImageSet>& images) {
  std::vector<Array> out;
  for (const vktg::ImageSet& image : images) out.push_back(toArray(image));
  return out;
}

// An input image, its layers named as `like`'s (the render's).
vktg::ImageSet fromArray(const InputArray& a, const vktg::Gate& gate) {
  vktg::ImageSet image;
  image.height = uint32_t(a.shape(0));
  image.width = uint32_t(a.shape(1));
  const size_t layers = a.shape(2), pixels = size_t(image.width) * image.height;
  const float* data = a.data();
  for (size_t l = 0; l < layers; ++l) {
    vktg::ImageLayer layer{l < gate.layers() ? gate.layerName(uint32_t(l)) : "L" + std::to_string(l), std::vector<float>(pixels)};
    for (size_t i = 0; i < pixels; ++i) layer.pixels[i] = data[i * layers + l];
    image.layers.push_back(std::move(layer));
  }
  return image;
}

// What every render call shares: the request's settings, and a progress hook that checks for
// Ctrl-C with the GIL held.
struct Settings {
  std::optional<uint32_t> spp, seed, maxDepth;
  std::optional<std::pair<uint32_t, uint32_t>> resolution;
  std::optional<std::string> gate;
  std::string nee = "auto";
  bool pilot = true;
  std::vector<vktg::View> views;
  std::function<void(double)> progress;
};

vktg::NeeMode neeMode(const std::string& name) {
  if (name == "auto") return vktg::NeeMode::Auto;
  if (name == "standard") return vktg::NeeMode::Standard;
  if (name == "ellipsoidal") return vktg::NeeMode::Ellipsoidal;
  if (name == "mis") return vktg::NeeMode::Mis;
  throw vktg::Error("nee: '" + name + "' is not one of auto, standard, ellipsoidal, mis");
}

void fill(vktg::RenderRequest& r, const Settings& s) {
  r.spp = s.spp;
  r.seed = s.seed;
  r.maxDepth = s.maxDepth;
  r.resolution = s.resolution;
  if (s.gate) r.gate = vktg::parseGateSpec(*s.gate, "gate");
  r.nee = neeMode(s.nee);
  r.pilot = s.pilot;
  r.views = s.views;
  const std::function<void(double)> callback = s.progress;
  r.progress = [callback](double fraction) {
    nb::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      PyErr_Clear();
      vktg::requestInterrupt(SIGINT);  // the render stops after this batch: vktg::Interrupted
      return;
    }
    if (callback) callback(fraction);
  };
}

// Runs `f` without the GIL, a pending interrupt forgotten first.
template <class F>
auto released(F&& f) {
  vktg::clearInterrupt();
  nb::gil_scoped_release release;
  return f();
}

vktg::Gate gateOf(const vktg::Model& model, const Settings& s) {
  return s.gate ? vktg::parseGateSpec(*s.gate, "gate") : model.scene().gate;
}

}  // namespace

NB_MODULE(_vktg, m) {
  m.doc() = "vktg's C++ API (vktg/vktg.h); use the vktg package, which wraps it.";
  // Scenes, views and contexts that a script's globals (or autograd's saved state) still hold when
  // the interpreter shuts down are freed after nanobind's own teardown, which would report them.
  nb::set_leak_warnings(false);
  static nb::exception<vktg::Error> error(m, "Error");
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const vktg::Interrupted& e) {
      vktg::clearInterrupt();
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    }
  });

  nb::class_<vktg::Context>(m, "Context")
      .def(
          "__init__",
          [](vktg::Context* self, const std::string& device, bool validation, uint64_t memoryMiB) {
            vktg::DeviceOptions o;
            o.device = device;
            o.validation = validation;
            o.memoryBudget = memoryMiB << 20;
            new (self) vktg::Context(o);
          },
          nb::arg("device") = "", nb::arg("validation") = false, nb::arg("memory_mib") = 0)
      .def_prop_ro("device_name", &vktg::Context::deviceName)
      .def_prop_ro("cpu_device", &vktg::Context::cpuDevice)
      .def_prop_ro("validation_messages", &vktg::Context::validationMessages);

  nb::class_<vktg::View>(m, "View");

  nb::class_<vktg::Model>(m, "Model")
      .def_static("load", [](const std::string& file) { return vktg::Model::load(file); })
      .def_static("parse", [](const std::string& text, const std::string& name, const std::string& baseDir) {
        return vktg::Model::parse(text, name, baseDir);
      })
      .def_static("built_in", &vktg::Model::builtIn)
      .def("copy", [](const vktg::Model& model) { return vktg::Model(model); })
      .def("parameter_names", &vktg::Model::parameterNames)
      .def("select", &vktg::Model::select)
      .def("value", &vktg::Model::value)
      .def("set_value", &vktg::Model::setValue)
      .def("values", &vktg::Model::values)
      .def("set_values", &vktg::Model::setValues)
      .def_prop_ro("width", [](const vktg::Model& model) { return vktg::imagePixels(model.scene().camera).x; })
      .def_prop_ro("height", [](const vktg::Model& model) { return vktg::imagePixels(model.scene().camera).y; })
      .def_prop_ro("gate", [](const vktg::Model& model) { return model.scene().gate.describe(); })
      .def_prop_ro("spp", [](const vktg::Model& model) { return model.scene().render.spp; })
      .def_prop_ro("seed", [](const vktg::Model& model) { return model.scene().render.seed; })
      .def_prop_ro("source", [](const vktg::Model& model) { return model.scene().source.string(); });

  nb::class_<Settings>(m, "Settings")
      .def(nb::init<>())
      .def_rw("spp", &Settings::spp)
      .def_rw("seed", &Settings::seed)
      .def_rw("max_depth", &Settings::maxDepth)
      .def_rw("resolution", &Settings::resolution)
      .def_rw("gate", &Settings::gate)
      .def_rw("nee", &Settings::nee)
      .def_rw("pilot", &Settings::pilot)
      .def_rw("views", &Settings::views)
      .def_rw("progress", &Settings::progress);

  m.def("gate_layers", [](const std::string& spec) { return vktg::parseGateSpec(spec, "gate").layers(); });
  m.def("describe_gate", [](const std::string& spec) { return vktg::parseGateSpec(spec, "gate").describe(); });
  // A view of the scene's camera with its own seed and point lights placed by name.
  m.def("view", [](const vktg::Model& model, uint32_t seed, const std::vector<std::pair<std::string, std::vector<float>>>& lights) {
    vktg::View view{model.scene().camera, seed, {}};
    const auto& pointLights = model.scene().pointLights;
    for (const auto& [name, position] : lights) {
      uint32_t index = 0;
      while (index < pointLights.size() && pointLights[index].name != name) ++index;
      if (index == pointLights.size()) throw vktg::Error("lights: the scene has no point light \"" + name + "\"");
      if (position.size() != 3) throw vktg::Error("lights: " + name + ": a position is three numbers");
      view.lightPositions.push_back({index, glm::vec3(position[0], position[1], position[2])});
    }
    return view;
  });
  // The views with other random numbers (the adjoint passes of vktg.torch): each seed mixed with `salt`.
  m.def("reseeded", [](std::vector<vktg::View> views, uint32_t salt) {
    for (vktg::View& v : views) v.seed = v.seed * 0x9E3779B1u + salt;
    return views;
  });
  m.def("scan_views", [](const vktg::Model& model, const std::string& file) { return vktg::scanViews(model, file); });

  m.def("render", [](vktg::Context& context, const vktg::Model& model, const Settings& settings) {
    vktg::RenderRequest request;
    fill(request, settings);
    vktg::Rendered r = released([&] { return vktg::render(context, model, request); });
    nb::dict out;
    out["images"] = toArrays(r.images);
    out["variances"] = toArrays(r.variances);
    out["plan"] = r.plan;
    out["non_finite"] = r.nonFinite;
    out["seconds"] = r.seconds;
    return out;
  });

  m.def("derivatives", [](vktg::Context& context, const vktg::Model& model, const std::vector<std::string>& parameters,
                          const Settings& settings, bool interior, bool edge, bool pathLength,
                          std::optional<bool> antithetic) {
    vktg::GradRequest request;
    fill(request, settings);
    request.interior = interior, request.edge = edge, request.pathLength = pathLength;
    request.antithetic = antithetic;
    vktg::Derivatives d = released([&] { return vktg::derivatives(context, model, parameters, request); });
    nb::dict out;
    out["parameters"] = d.parameters;
    out["image"] = toArray(d.image);
    out["total"] = toArrays(d.total);
    out["total_variance"] = toArrays(d.totalVariance);
    out["interior"] = toArrays(d.interior);
    out["edge"] = toArrays(d.edge);
    out["pathlength"] = toArrays(d.pathLength);
    out["plan"] = d.plan;
    return out;
  });

  m.def("render_backward", [](vktg::Context& context, const vktg::Model& model, const std::vector<std::string>& parameters,
                              const std::vector<InputArray>& adjoints, const Settings& settings, bool interior, bool edge,
                              bool pathLength, std::optional<bool> antithetic) {
    vktg::GradRequest request;
    fill(request, settings);
    request.interior = interior, request.edge = edge, request.pathLength = pathLength;
    request.antithetic = antithetic;
    const vktg::Gate gate = gateOf(model, settings);
    std::vector<vktg::ImageSet> images;
    for (const InputArray& a : adjoints) images.push_back(fromArray(a, gate));
    return released([&] { return vktg::renderBackward(context, model, parameters, images, request); });
  });
}
